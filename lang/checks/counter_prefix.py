"""LD105: a counter instruction on a name that does not start with C."""

from __future__ import annotations

from ..codes import register
from ..values import is_literal
from ..diagnostics import warning
from .common import COUNTERS, arg_span, rung_no, token

CODE = register(
    "LD105", "counter name does not start with C",
    "Counters (CTU, CTD, CTC, CTR) keep their count in a variable whose name starts with C; "
    "LDmicro's counter dialog keeps that letter. Another first letter gives the counter a name that "
    "reads as something else.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind(*COUNTERS):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and not name.startswith("C"):
            found.append(warning(
                CODE,
                f"{element.kind} counter '{name}' in {rung_no(rung)}: counter names start with C (e.g. 'C{name}')",
                arg_span(element, "name"),
            ))
    return found
