"""LD108: an A name written by something other than READ ADC."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import COUNTERS, TIMERS
from ..labels import label
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS

_SKIP = frozenset(("READ_ADC", "RES") + TIMERS + COUNTERS)  # those have their own rules


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, uses in index.uses.items():
        if not name.startswith("A"):
            continue
        for use in uses:
            if use.writes and use.element.kind not in _SKIP:
                found.append(report(
                    CODE,
                    f"{label(use.element)} in {rung_no(use.rung)} writes '{name}', an A/D input "
                    "that only READ ADC should write; use a general variable",
                    use.span,
                ))
    return found
