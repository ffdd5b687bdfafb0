"""LD311: a timer delay shorter than one PLC cycle."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, delay_text, rung_no, timer_periods, timer_text

CODE = register(
    "LD311", "timer delay shorter than the cycle time",
    "Timers count PLC cycles: the period is the delay divided by the cycle time, rounded down. A "
    "delay shorter than one cycle gives a period of 0 cycles. LDmicro: \"Timer period too short "
    "(needs faster cycle time). Or increase timer period.\" Lengthen the delay or shorten the "
    "cycle time.",
)


def check(program, index):
    cycle = program.settings.cycle_us
    return [
        error(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: the delay {delay_text(delay)} is shorter than "
            f"the PLC cycle time {delay_text(cycle)}; lengthen the delay or shorten the cycle",
            arg_span(element, "delay"),
        )
        for rung, element, delay, adjust, period, adjusted in timer_periods(program, index)
        if delay > 0 and period is not None and period < 1
    ]
