"""LD104: a timer instruction on a name that does not start with T."""

from __future__ import annotations

from ..codes import register
from .common import TIMERS, misnamed

CODE = register(
    "LD104", "timer name does not start with T",
    "Timers (TON, TOF, RTO, RTL, TCY, THI, TLO) keep their count in a variable whose name starts "
    "with T; LDmicro's timer dialog forces that letter. Another first letter gives the timer a name "
    "that reads as something else (an input, a counter, a plain variable).",
)


def check(program, index):
    return misnamed(index, CODE, TIMERS, "T", "timer")
