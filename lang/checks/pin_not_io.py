"""LD403: a name assigned to a pin that is not an I/O pin."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import is_analog, pin_text, used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    device = index.device
    for name, assignment, pin in used_pins(program, index):
        if pin is None or pin.is_io:
            continue
        if is_analog(index, name) and pin.name in device.adc:
            continue
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, which is {pin.name} on the "
            f"{device.title}, not an input/output pin",
            assignment.span,
        ))
    return found
