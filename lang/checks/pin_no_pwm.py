"""LD405: a PWM output on a pin without PWM."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import pin_text, pwm_names, used_pins

CODE = register(
    "LD405", "PWM output on a pin without PWM",
    "P names (and any name SET PWM drives) must sit on a pin a hardware PWM unit drives (OC0A, "
    "CCP1...). LDmicro: \"Pin '...': PWM output not available!\". Choose one of the part's PWM pins.",
)


def check(program, index):
    found = []
    device = index.device
    pwm = pwm_names(index)
    for name, assignment, pin in used_pins(program, index):
        if pin is None or name not in pwm or pin.name in device.pwm or not pin.is_io:
            continue
        choices = ", ".join(sorted(n for n in device.pwm if device.pin(n) is not None)) or "none"
        found.append(error(
            CODE,
            f"PWM output '{name}' is assigned to {pin_text(assignment)} ({pin.name}), which has no PWM "
            f"on the {device.title}; PWM pins: {choices}",
            assignment.span,
        ))
    return found
