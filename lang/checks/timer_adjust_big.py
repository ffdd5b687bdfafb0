"""LD313: a timer adjust as large as the period itself."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, arg_span, delay_text, rung_no, timer_periods, timer_text

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return [
        report(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: the adjust {adjust} is not smaller than the "
            f"period of {period} cycle(s) ({delay_text(delay)}); decrease the adjust value",
            arg_span(element, "delay"),
        )
        for rung, element, delay, adjust, period, adjusted in timer_periods(program, index)
        if delay > 0 and period is not None and period >= 1 and adjusted > 0 and period <= adjust
    ]
