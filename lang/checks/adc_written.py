"""LD108: an A name written by something other than READ ADC."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import COUNTERS, TIMERS, label, rung_no

CODE = register(
    "LD108", "A/D name written by another instruction",
    "A names hold the result of READ ADC and are bound to an analog input pin. Any instruction may "
    "read them as integers, but only READ ADC should write them: a MOV or ADD into an A name "
    "overwrites the reading and still claims an ADC pin. Use a general variable for computed values.",
)

_SKIP = frozenset(("READ_ADC", "RES") + TIMERS + COUNTERS)  # those have their own rules


def check(program, index):
    found = []
    for name, uses in index.uses.items():
        if not name.startswith("A"):
            continue
        for use in uses:
            if use.writes and use.element.kind not in _SKIP:
                found.append(warning(
                    CODE,
                    f"{label(use.element)} in {rung_no(use.rung)} writes '{name}', an A/D input "
                    "that only READ ADC should write; use a general variable",
                    use.span,
                ))
    return found
