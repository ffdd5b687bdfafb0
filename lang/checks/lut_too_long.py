"""LD309: a look-up table with more than 64 values."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, token

CODE = register(
    "LD309", "look-up table longer than 64 values",
    "LDmicro keeps at most 64 entries in a look-up table (its loader does not check the count, and "
    "a longer table overruns its memory). Split the table, or compute the values.",
)

LIMIT = 64


def check(program, index):
    found = []
    for rung, element in index.of_kind("LOOK_UP_TABLE"):
        count = len(element.args.get("values") or ())
        if count > LIMIT:
            table = token(element.args.get("table"))
            name = f" '{table}'" if table else ""
            found.append(error(
                CODE,
                f"LUT table{name} in {rung_no(rung)} has {count} values; at most {LIMIT} are allowed",
                arg_span(element, "values"),
            ))
    return found
