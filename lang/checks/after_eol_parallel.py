"""LD202: something after a parallel block that holds an end-of-line branch."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex
from ..labels import describe
from ..model import Parallel, Program
from .common import RUNGS, node_span, node_text, rung_no, terminal

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
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
        found.append(report(
            CODE,
            f"{node_text(after)} in {rung_no(rung)} follows a parallel block whose branch ends in "
            f"{describe(end)}: nothing may follow such a block",
            node_span(after),
            *related,
        ))
    return found
