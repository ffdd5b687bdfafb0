"""LD209: GOSUB to a rung number."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, token

CODE = register(
    "LD209", "GOSUB to a number",
    "Unlike GOTO, GOSUB cannot target a rung number: it needs the name of a SUBPROG. LDmicro: "
    "\"GOSUB: SUBPROG as number '...' not allowed !\".",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("GOSUB"):
        name = token(element.args.get("label"))
        if name.isdigit():
            found.append(error(
                CODE,
                f"GOSUB '{name}' in {rung_no(rung)}: GOSUB needs a SUBPROG name, not a rung number",
                arg_span(element, "label"),
            ))
    return found
