"""LD213: a rung with no element at all."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import rung_no

CODE = register(
    "LD213", "rung without elements",
    "A .ld file can hold a RUNG ... END block with nothing in it (LDmicro's own samples have one). "
    "LDmicro loads and compiles it as a rung that does nothing, unlike an empty rung drawn in the "
    "editor (PLACEHOLDER, LD212), which it refuses. Delete it.",
)


def check(program, index):
    return [
        warning(CODE, f"{rung_no(number)} has no elements and does nothing; delete it", rung.span)
        for number, rung in enumerate(program.rungs)
        if not rung.circuit.items
    ]
