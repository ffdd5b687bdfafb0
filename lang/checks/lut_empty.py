"""LD308: a look-up table with no values."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import rung_no, token

CODE = register(
    "LD308", "look-up table with no values",
    "A LUT instruction reads entry [index] of its table; with no entries every index is out of "
    "range. List the values in the DETAILS section (a text export does not carry them).",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("LOOK_UP_TABLE"):
        if not element.args.get("values"):
            table = token(element.args.get("table"))
            name = f" '{table}'" if table else ""
            found.append(error(CODE, f"LUT table{name} in {rung_no(rung)} has no values", element.span))
    return found
