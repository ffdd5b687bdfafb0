"""LD213: a rung with no element at all."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return [
        report(CODE, f"{rung_no(number)} has no elements and does nothing; delete it", program.rungs[number].span)
        for number in index.rungs
        if not program.rungs[number].circuit.items
    ]
