"""LD708: a SET PWM its part's timer cannot make: an output of a timer the
back end does not drive, a frequency of 0 or less, two outputs of one
timer asking for different frequencies (they share its period), or two
names on the pins of one CCP (the PIC16F1824's CCP1 on RC5 or RC4)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import PwmSetting, pwm_refusal, pwm_setting, pwm_timer
from ..index import ProgramIndex
from ..model import Program
from .common import pwm_outputs

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    found = []
    timers: dict[int, PwmSetting] = {}
    names: dict[str, str] = {}
    for _, element, unit, freq in pwm_outputs(program, index):
        why = pwm_refusal(device, unit, freq)
        name = str(element.args.get("name"))
        if why is None and names.setdefault(unit, name) != name:
            why = (f"'{names[unit]}' and '{name}' are both outputs of {unit}, which drives one of its pins at a "
                   "time: use one name, or a pin of another CCP")
        if why is not None:
            found.append(report(CODE, why, element.span))
            continue
        timer = pwm_timer(device, unit)
        assert timer is not None  # pwm_refusal says it drives the unit
        number = timer["timer"]
        setting = pwm_setting(device, unit, program.settings.crystal_hz, freq)
        if timers.setdefault(number, setting) != setting:
            found.append(report(CODE, f"the outputs of Timer{number} ask for different PWM frequencies; "
                                      "they share the timer, so they need the same one", element.span))
    return found
