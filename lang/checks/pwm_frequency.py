"""LD709: a SET PWM whose frequency the part's timer only approximates."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import approximated, pwm_refusal, pwm_setting
from ..index import ProgramIndex
from ..model import Program
from .common import pwm_outputs

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    found = []
    for _, element, unit, freq in pwm_outputs(program, index):
        if pwm_refusal(device, unit, freq) is not None:
            continue  # LD708
        setting = pwm_setting(device, unit, program.settings.crystal_hz, freq)
        if approximated(setting, freq):
            found.append(report(CODE, f"PWM on {unit} runs at {setting.freq:.1f} Hz (asked {freq} Hz)",
                                element.span))
    return found
