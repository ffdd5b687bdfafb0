"""LD322: a formatted string that inserts a variable but names none."""

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
        interpolations = scan_format(token(element.args.get("text")))[0]
        if interpolations and not token(element.args.get("var")):
            found.append(report(
                CODE,
                f"formatted string in {rung_no(rung)} inserts a variable ({interpolations[0]}) but names none",
                arg_span(element, "text"),
            ))
    return found
