"""LD312: a timer adjust that brings the period to zero or below."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, delay_text, rung_no, timer_periods, timer_text

CODE = register(
    "LD312", "timer adjust leaves no delay",
    "The adjust value (in PLC cycles) is added to a timer's period; old LDmicro0.1 files get -1 for "
    "TON, TOF and RTO. When the adjusted period is 0 cycles or less the timer cannot work. LDmicro: "
    "\"Timer '...': Total timer delay cannot be zero or negative. Increase the adjust value!\"",
)


def check(program, index):
    return [
        error(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: the delay {delay_text(delay)} is {period} cycle(s), "
            f"and the adjust {adjust} leaves {adjusted}; increase the adjust value or the delay",
            arg_span(element, "delay"),
        )
        for rung, element, delay, adjust, period, adjusted in timer_periods(program, index)
        if delay > 0 and period is not None and period >= 1 and adjusted <= 0
    ]
