"""LD306: PWL x values that are not strictly increasing."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, table_numbers

CODE = register(
    "LD306", "PWL x values not strictly increasing",
    "The x values of a piecewise-linear table must grow from each point to the next: the "
    "instruction finds the segment of its index by comparing with them in order. LDmicro: \"x "
    "values in piecewise linear table must be strictly increasing.\"",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("PIECEWISE_LINEAR"):
        points = element.args.get("points") or ()
        xs = table_numbers([p[0] for p in points])
        if xs is None:
            continue
        for i in range(1, len(xs)):
            if xs[i] <= xs[i - 1]:
                found.append(error(
                    CODE,
                    f"PWL in {rung_no(rung)}: point {i} has x = {xs[i]}, not greater than "
                    f"x = {xs[i - 1]} of point {i - 1}; x values must be strictly increasing",
                    arg_span(element, "points"),
                ))
                break
    return found
