"""LD104: a timer instruction on a name that does not start with T."""

from __future__ import annotations

from ..codes import register
from ..values import is_literal
from ..diagnostics import warning
from .common import TIMERS, arg_span, rung_no, token

CODE = register(
    "LD104", "timer name does not start with T",
    "Timers (TON, TOF, RTO, RTL, TCY, THI, TLO) keep their count in a variable whose name starts "
    "with T; LDmicro's timer dialog forces that letter. Another first letter gives the timer a name "
    "that reads as something else (an input, a counter, a plain variable).",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind(*TIMERS):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and not name.startswith("T"):
            found.append(warning(
                CODE,
                f"{element.kind} timer '{name}' in {rung_no(rung)}: timer names start with T (e.g. 'T{name}')",
                arg_span(element, "name"),
            ))
    return found
