"""LD411: a pin assigned to a name the program does not use."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from ..roles import BUS_PIN_SUFFIXES
from .common import pin_text

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, assignment in program.pins.items():
        if name in index.uses or not assignment.assigned:
            continue
        if name == "YPlcCycleDuty" and program.settings.cycle_duty:
            continue
        if any(suffix in name for suffix in BUS_PIN_SUFFIXES):
            continue
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)} but the program does not use it",
            assignment.span,
        ))
    return found
