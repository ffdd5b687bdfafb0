"""LD504: SET PWM on a part without PWM."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if device is None or device.pwm:
        return []
    return [
        report(CODE, f"SET PWM in {rung_no(rung)}: the {device.title} has no PWM output", element.span)
        for rung, element in index.of_kind("SET_PWM")
    ]
