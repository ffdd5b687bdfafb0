"""LD204: SUBPROG or ENDSUB that shares its rung with other elements."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, token

CODE = register(
    "LD204", "SUBPROG or ENDSUB not alone in its rung",
    "SUBPROG and ENDSUB mark where a subroutine starts and ends; each must be the only element of "
    "its rung. LDmicro: \"SUBPROG: '...' declaration must be a single inside the rung\".",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("SUBPROG", "ENDSUB"):
        items = program.rungs[rung].circuit.items
        if len(items) == 1 and items[0] is element:
            continue
        name = token(element.args.get("label"))
        found.append(error(
            CODE,
            f"{element.kind} '{name}' in {rung_no(rung)} must be the only element of its rung",
            element.span or arg_span(element, "label"),
        ))
    return found
