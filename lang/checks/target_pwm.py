"""LD504: SET PWM on a part without PWM."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import rung_no

CODE = register(
    "LD504", "SET PWM on a part without PWM",
    "The selected part has no hardware PWM output LDmicro can use, so SET PWM cannot be compiled "
    "for it. LDmicro: \"PWM function used but not supported for this micro.\"",
)


def check(program, index):
    device = index.device
    if device is None or device.pwm:
        return []
    return [
        error(CODE, f"SET PWM in {rung_no(rung)}: the {device.title} has no PWM output", element.span)
        for rung, element in index.of_kind("SET_PWM")
    ]
