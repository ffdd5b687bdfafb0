"""LD130: an internal relay that is read but never written."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import label, read_never_written, rung_no

CODE = register(
    "LD130", "internal relay read but never written",
    "An R name is an internal relay: a bit in memory that only the program sets, through a coil "
    "(or a set/reset coil, or another instruction that writes bits). A relay that is read but never "
    "written is always 0, which is almost always a misspelt name or a forgotten coil. LDmicro "
    "refuses to compile such a program (\"Internal relay '...' never assigned; add its coil "
    "somewhere.\") but simulates it.",
)


def check(program, index):
    found = []
    for name, first_read in read_never_written(index):
        if not name.startswith("R"):
            continue
        found.append(warning(
            CODE,
            f"internal relay '{name}' is read by {label(first_read.element)} in "
            f"{rung_no(first_read.rung)} but no coil ever writes it: it is always 0",
            first_read.span,
        ))
    return found
