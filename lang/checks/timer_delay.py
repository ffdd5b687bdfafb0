"""LD310: a timer delay of zero or less."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, arg_span, rung_no, timer_periods, timer_text

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return [
        report(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: the delay ({delay} us) must be greater than zero",
            arg_span(element, "delay"),
        )
        for rung, element, delay, adjust, period, adjusted in timer_periods(program, index)
        if delay <= 0
    ]
