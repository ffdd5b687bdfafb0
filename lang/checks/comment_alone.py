"""LD203: a COMMENT that shares its rung with other elements."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import rung_no

CODE = register(
    "LD203", "comment not alone in its rung",
    "A comment is a rung of its own: LDmicro's editor keeps it alone, and its compiler skips every "
    "rung that starts with a comment, so instructions beside a comment never run. Move the "
    "instructions to a rung of their own.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("COMMENT"):
        items = program.rungs[rung].circuit.items
        if len(items) == 1 and items[0] is element:
            continue
        found.append(error(
            CODE,
            f"the comment in {rung_no(rung)} must be alone in its rung; the rung also holds other "
            "elements, which would never run",
            element.span,
        ))
    return found
