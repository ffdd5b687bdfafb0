"""LD314: a timer delay too long to count."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, arg_span, delay_text, rung_no, timer_periods, timer_text

CODE = rule_code(__name__)
SCOPE = RUNGS

MAX = (1 << 31) - 1


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element, delay, _adjust, period, adjusted in timer_periods(program, index):
        if delay > MAX:
            reason = (f"the delay {delay_text(delay)} ({delay} us) is more than the maximum "
                      "2147483647 us (35.79 min)")
        elif adjusted is not None and max(period, adjusted) > MAX:
            reason = f"the period of {max(period, adjusted)} cycles does not fit a 32-bit timer"
        else:
            continue
        found.append(report(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: {reason}",
            arg_span(element, "delay"),
        ))
    return found
