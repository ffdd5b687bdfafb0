"""LD404: an A/D input on a pin without an A/D converter channel."""

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
        if pin is None or not is_analog(index, name) or pin.name in device.adc:
            continue
        if not pin.is_io:
            continue  # LD403 says it
        choices = ", ".join(sorted(n for n in device.adc if device.pin(n) is not None)) or "none"
        found.append(report(
            CODE,
            f"A/D input '{name}' is assigned to {pin_text(assignment)} ({pin.name}), which has no A/D "
            f"channel on the {device.title}; analog pins: {choices}",
            assignment.span,
        ))
    return found
