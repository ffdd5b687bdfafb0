"""LD102: a coil (or set/reset/toggle coil) writing an X input."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, label, rung_no, token

CODE = register(
    "LD102", "coil writes an input",
    "An X name is an input pin: the program can read it with a contact but never drive it. A coil, "
    "set, reset or toggle coil on an X name is refused by LDmicro (a coil must be Y, R or M). Use an "
    "output (Y) or an internal relay (R).",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("COIL"):
        name = token(element.args.get("name"))
        if name.startswith("X"):
            found.append(error(
                CODE,
                f"{label(element)} '{name}' in {rung_no(rung)} writes an input pin: "
                "X names can only be read; write an output (Y) or a relay (R)",
                arg_span(element, "name"),
            ))
    return found
