"""LD315: timers in a program whose cycle time is 0."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import TIMERS, rung_no, timer_text

CODE = register(
    "LD315", "timers with a cycle time of 0",
    "With a PLC cycle time of 0 the program runs free, as fast as it can, so a scan has no fixed "
    "length and timers, which count scans, measure no time: LDmicro gives every timer a period of "
    "one scan. LDmicro: \"PLC Cycle Time is '0'. TON, TOF, RTO, RTL, TCY timers does not work "
    "correctly!\" Set a cycle time.",
)


def check(program, index):
    if program.settings.cycle_us > 0:
        return []
    timers = index.of_kind(*TIMERS)
    if not timers:
        return []
    rung, element = timers[0]
    return [warning(
        CODE,
        f"the PLC cycle time is 0, so {timer_text(element)} in {rung_no(rung)} and every other timer "
        "measure no time (each counts one scan); set a cycle time",
        element.span,
    )]
