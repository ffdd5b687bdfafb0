"""LD107: SET PWM on a name that does not start with P."""

from __future__ import annotations

from ..codes import register
from ..values import is_literal
from ..diagnostics import error
from .common import arg_span, rung_no, token

CODE = register(
    "LD107", "PWM output name does not start with P",
    "SET PWM drives a PWM output pin, whose name starts with P (LDmicro adds the P itself when it "
    "reads an old file). Without it the name is not a pin and cannot be assigned to a PWM output.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("SET_PWM"):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and not name.startswith("P"):
            found.append(error(
                CODE,
                f"SET PWM '{name}' in {rung_no(rung)}: a PWM output name starts with P (e.g. 'P{name}')",
                arg_span(element, "name"),
            ))
    return found
