"""LD105: a counter instruction on a name that does not start with C."""

from __future__ import annotations

from ..codes import register
from .common import COUNTERS, misnamed

CODE = register(
    "LD105", "counter name does not start with C",
    "Counters (CTU, CTD, CTC, CTR) keep their count in a variable whose name starts with C; "
    "LDmicro's counter dialog keeps that letter. Another first letter gives the counter a name that "
    "reads as something else.",
)


def check(program, index):
    return misnamed(index, CODE, COUNTERS, "C", "counter")
