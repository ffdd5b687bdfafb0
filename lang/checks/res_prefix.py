"""LD106: RES on a name that does not start with T, C or P."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from ..values import is_literal
from .common import RUNGS, arg_span, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("RES"):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and name[0] not in "TCP":
            found.append(report(
                CODE,
                f"RES '{name}' in {rung_no(rung)}: RES resets a timer (T), counter (C) or PWM output (P); "
                "clear a variable with MOV 0 or a bit with a reset coil",
                arg_span(element, "name"),
            ))
    return found
