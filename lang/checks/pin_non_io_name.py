"""LD410: a pin assigned to a name that is no I/O."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import BUS_PIN_SUFFIXES, adc_names, is_assigned, pin_text, pwm_names

CODE = register(
    "LD410", "pin assigned to a name that is not an I/O",
    "Only inputs (X), outputs (Y), A/D inputs (A) and PWM outputs (P) take pins. A pin given to a "
    "relay, timer, counter or variable does nothing (a pin on a name the program does not use at "
    "all is LD411). LDmicro: \"Can only assign pin number to input/output pins (Xname or Yname or "
    "Aname or Pname).\"",
)


def check(program, index):
    found = []
    analog = pwm = None
    for name, assignment in program.pins.items():
        if not is_assigned(assignment) or name[:1] in ("X", "Y", "A", "P") or name not in index.uses:
            continue
        if any(suffix in name for suffix in BUS_PIN_SUFFIXES):
            continue
        if analog is None:
            analog, pwm = adc_names(index), pwm_names(index)
        if name in analog or name in pwm:
            continue
        found.append(warning(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, but only X, Y, A and P names take pins",
            assignment.span,
        ))
    return found
