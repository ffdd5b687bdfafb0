"""LD310: a timer delay of zero or less."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, timer_periods, timer_text

CODE = register(
    "LD310", "timer delay zero or negative",
    "A timer's delay must be a positive time. LDmicro: \"Timer '...': Delay cannot be zero or "
    "negative.\"",
)


def check(program, index):
    return [
        error(
            CODE,
            f"{timer_text(element)} in {rung_no(rung)}: the delay ({delay} us) must be greater than zero",
            arg_span(element, "delay"),
        )
        for rung, element, delay, adjust, period, adjusted in timer_periods(program, index)
        if delay <= 0
    ]
