"""LD412: an output (a Y name, a PWM output) on a pin that can only be an
input: the MCLR pin of the PIC parts that double it as an input (RE3 of the
PIC16F88x, RA5 of the 16F628 and 16F8x, GP3 of the 12F675/683)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import is_pwm, pin_text, used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    found = []
    for name, assignment, pin in used_pins(program, index):
        if pin is None or not pin.input_only or not (name.startswith("Y") or is_pwm(index, name)):
            continue
        found.append(report(
            CODE,
            f"output '{name}' is assigned to {pin_text(assignment)} ({pin.name}), which can only be an input "
            f"on the {device.title}: the pin has no output driver",
            assignment.span,
        ))
    return found
