"""LD311: a timer delay shorter than one PLC cycle."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, arg_span, delay_text, rung_no, timer_periods, timer_text

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    cycle = program.settings.cycle_us
    return [
        report(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: the delay {delay_text(delay)} is shorter than "
            f"the PLC cycle time {delay_text(cycle)}; lengthen the delay or shorten the cycle",
            arg_span(element, "delay"),
        )
        for rung, element, delay, adjust, period, adjusted in timer_periods(program, index)
        if delay > 0 and period is not None and period < 1
    ]
