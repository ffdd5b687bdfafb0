"""LD212: an empty rung."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import rung_no

CODE = register(
    "LD212", "empty rung",
    "A rung with no instruction (drawn as a bare `--`, PLACEHOLDER in a .ld file) cannot be "
    "compiled. LDmicro: \"Empty row; delete it or add instructions before compiling.\"",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("PLACEHOLDER"):
        found.append(error(
            CODE,
            f"{rung_no(rung)} is empty; delete it or add instructions",
            element.span or program.rungs[rung].span,
        ))
    return found
