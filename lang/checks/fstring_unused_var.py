"""LD323: a formatted string that names a variable its text never inserts."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import RUNGS, arg_span, rung_no, scan_format

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("FORMATTED_STRING"):
        var = token(element.args.get("var"))
        if var and not scan_format(token(element.args.get("text")))[0]:
            found.append(report(
                CODE,
                f"formatted string in {rung_no(rung)} names the variable '{var}' but its text has no "
                "\\1..\\5 escape to insert it (e.g. \\-3), so the variable is not used; add one or leave "
                "the variable blank",
                arg_span(element, "var"),
            ))
    return found
