"""LD202: something after a parallel block that holds an end-of-line branch."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import Related, error
from ..model import Parallel
from .common import describe, node_span, node_text, rung_no, terminal

CODE = register(
    "LD202", "element after a parallel that ends in an end-of-line instruction",
    "When a branch of a parallel block ends in an end-of-line instruction (a coil, MOV, RES...), the "
    "block has no output: LDmicro does not even compute it, so nothing may follow the block in its "
    "series. Move the following elements into the branches that need them, or into a rung of "
    "their own.",
)


def check(program, index):
    found = []
    for rung, series, position in index.followed:
        items = series.items
        item = items[position]
        if item.__class__ is not Parallel:
            continue
        end = terminal(item)
        if end is None:
            continue
        after = items[position + 1]
        related = [Related(end.span, f"this {describe(end)} ends a branch of the parallel")] if end.span else []
        found.append(error(
            CODE,
            f"{node_text(after)} in {rung_no(rung)} follows a parallel block whose branch ends in "
            f"{describe(end)}: nothing may follow such a block",
            node_span(after),
            *related,
        ))
    return found
