"""LD307: a PWL segment whose interpolation overflows 16-bit arithmetic."""

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
        ys = table_numbers([p[1] for p in points])
        if xs is None or ys is None:
            continue
        for i in range(len(xs) - 1, 0, -1):
            dx, dy = xs[i] - xs[i - 1], ys[i] - ys[i - 1]
            product = dx * dy
            if product >= 32767 or product <= -32768:
                found.append(report(
                    CODE,
                    f"PWL in {rung_no(rung)}: the segment from point {i - 1} to point {i} has "
                    f"dx * dy = {dx} * {dy} = {product}, beyond 16-bit math; make the entries smaller "
                    "or put the points closer together",
                    arg_span(element, "points"),
                ))
                break
    return found
