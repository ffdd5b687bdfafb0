"""LD411: a pin assigned to a name the program does not use."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..iolist import bus_pin
from ..model import Program
from ..roles import CYCLE_DUTY_PIN
from .common import pin_text

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, assignment in program.pins.items():
        if name in index.uses or not assignment.assigned:
            continue
        if name == CYCLE_DUTY_PIN and program.settings.cycle_duty:
            continue
        if bus_pin(name):
            continue
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)} but the program does not use it",
            assignment.span,
        ))
    return found
