"""LD305: a piecewise-linear table with no points."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import rung_no, token

CODE = register(
    "LD305", "piecewise-linear table with no points",
    "A PWL instruction interpolates between the (x, y) points of its table; with no points there "
    "is nothing to interpolate. LDmicro: \"Piecewise linear lookup table with zero elements!\". "
    "List the points in the DETAILS section.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("PIECEWISE_LINEAR"):
        if not element.args.get("points"):
            table = token(element.args.get("table"))
            name = f" '{table}'" if table else ""
            found.append(error(
                CODE,
                f"PWL table{name} in {rung_no(rung)} has no points",
                element.span,
            ))
    return found
