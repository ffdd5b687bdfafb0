"""LD103: a coil on a name that is not Y, R or M (X has its own rule, LD102)."""

from __future__ import annotations

from ..codes import register
from ..values import is_literal
from ..diagnostics import error
from .common import arg_span, label, rung_no, token

CODE = register(
    "LD103", "coil on a name that is not an output bit",
    "A coil writes one bit: its name must start with Y (output pin), R (internal relay) or M "
    "(Modbus coil). To store a number use MOV; to reset a timer or counter use RES. LDmicro stops "
    "with an internal error on any other coil name.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("COIL"):
        name = token(element.args.get("name"))
        if not name or is_literal(name) or name[0] in "YRMX":
            continue
        found.append(error(
            CODE,
            f"{label(element)} '{name}' in {rung_no(rung)} must name an output bit "
            "(Y output, R relay or M Modbus coil)",
            arg_span(element, "name"),
        ))
    return found
