"""LD403: a name assigned to a pin that is not an I/O pin."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import adc_names, pin_text, used_pins

CODE = register(
    "LD403", "pin is not an I/O pin",
    "Power, ground, reset, crystal and reference pins (VCC, GND, AREF...) cannot be inputs or "
    "outputs. Only an A/D input may use an analog-only pin (ADC6 and ADC7 of the 32-pin AVRs). "
    "LDmicro: \"Can only assign pin number to input/output pins\".",
)


def check(program, index):
    found = []
    device = index.device
    analog = None
    for name, assignment, pin in used_pins(program, index):
        if pin is None or pin.is_io:
            continue
        if analog is None:
            analog = adc_names(index)
        if name in analog and pin.name in device.adc:
            continue
        found.append(error(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, which is {pin.name} on the "
            f"{device.title}, not an input/output pin",
            assignment.span,
        ))
    return found
