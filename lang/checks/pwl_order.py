"""LD306: PWL x values that are not strictly increasing."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, arg_span, rung_no, table_numbers, table_of

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("PIECEWISE_LINEAR"):
        points = table_of(element, "points")
        xs = table_numbers([p[0] for p in points])
        if xs is None:
            continue
        for i in range(1, len(xs)):
            if xs[i] <= xs[i - 1]:
                found.append(report(
                    CODE,
                    f"PWL in {rung_no(rung)}: point {i} has x = {xs[i]}, not greater than "
                    f"x = {xs[i - 1]} of point {i - 1}; x values must be strictly increasing",
                    arg_span(element, "points"),
                ))
                break
    return found
