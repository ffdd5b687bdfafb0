"""LD405: a PWM output on a pin without PWM."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import is_pwm, pin_text, used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    device = index.device
    for name, assignment, pin in used_pins(program, index):
        if pin is None or not is_pwm(index, name) or pin.name in device.pwm or not pin.is_io:
            continue
        choices = ", ".join(sorted(n for n in device.pwm if device.pin(n) is not None)) or "none"
        found.append(report(
            CODE,
            f"PWM output '{name}' is assigned to {pin_text(assignment)} ({pin.name}), which has no PWM "
            f"on the {device.title}; PWM pins: {choices}",
            assignment.span,
        ))
    return found
