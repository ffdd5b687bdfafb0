"""LD320: a bad escape in a formatted string."""

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
        text = token(element.args.get("text"))
        for sequence, reason in scan_format(text)[1]:
            found.append(report(
                CODE,
                f"formatted string in {rung_no(rung)}: bad escape '{sequence}': {reason}",
                arg_span(element, "text"),
            ))
    return found
