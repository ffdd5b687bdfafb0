"""LD106: RES on a name that does not start with T, C or P."""

from __future__ import annotations

from ..codes import register
from ..values import is_literal
from ..diagnostics import warning
from .common import arg_span, rung_no, token

CODE = register(
    "LD106", "RES on a name that is not T, C or P",
    "RES resets a timer (T name), a counter (C name) or switches a PWM output off (P name); "
    "LDmicro's dialog offers only these three. To clear a plain variable use MOV with 0; to clear "
    "a bit use a reset coil (R).",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("RES"):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and name[0] not in "TCP":
            found.append(warning(
                CODE,
                f"RES '{name}' in {rung_no(rung)}: RES resets a timer (T), counter (C) or PWM output (P); "
                "clear a variable with MOV 0 or a bit with a reset coil",
                arg_span(element, "name"),
            ))
    return found
