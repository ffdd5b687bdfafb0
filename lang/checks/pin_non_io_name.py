"""LD410: a pin assigned to a name that is no I/O."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..iolist import bus_pin
from ..model import Program
from .common import is_analog, is_pwm, pin_text

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, assignment in program.pins.items():
        if not assignment.assigned or name[:1] in ("X", "Y", "A", "P") or name not in index.uses:
            continue
        if bus_pin(name):
            continue
        if is_analog(index, name) or is_pwm(index, name):
            continue
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, but only X, Y, A and P names take pins",
            assignment.span,
        ))
    return found
