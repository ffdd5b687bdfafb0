"""LD209: GOSUB to a rung number."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import RUNGS, arg_span, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("GOSUB"):
        name = token(element.args.get("label"))
        if name.isdigit():
            found.append(report(
                CODE,
                f"GOSUB '{name}' in {rung_no(rung)}: GOSUB needs a SUBPROG name, not a rung number",
                arg_span(element, "label"),
            ))
    return found
