"""LD104: a timer instruction on a name that does not start with T."""

from __future__ import annotations

from ..codes import rule_code
from ..instructions import TIMERS
from .common import RUNGS, misnamed

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program, index):
    return misnamed(index, CODE, TIMERS, "T", "timer")
