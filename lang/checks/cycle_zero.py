"""LD315: timers in a program whose cycle time is 0."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import TIMERS
from ..model import Program
from .common import rung_no, timer_text

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    if program.settings.cycle_us > 0:
        return []
    timers = index.of_kind(*TIMERS)
    if not timers:
        return []
    rung, element = timers[0]
    return [report(
        CODE,
        f"the PLC cycle time is 0, so {timer_text(element)} in {rung_no(rung)} and every other timer "
        "measure no time (each counts one scan); set a cycle time",
        element.span,
    )]
