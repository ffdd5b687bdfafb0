"""LD203: a COMMENT that shares its rung with other elements."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("COMMENT"):
        items = program.rungs[rung].circuit.items
        if len(items) == 1 and items[0] is element:
            continue
        found.append(report(
            CODE,
            f"the comment in {rung_no(rung)} must be alone in its rung; the rung also holds other "
            "elements, which would never run",
            element.span,
        ))
    return found
