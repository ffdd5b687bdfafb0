"""LD201: an end-of-line instruction that is not the last of its branch."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import describe
from ..model import Element, Program
from .common import RUNGS, node_text, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, series, position in index.followed:
        items = series.items
        item = items[position]
        if item.__class__ is Element:
            found.append(report(
                CODE,
                f"{describe(item)} in {rung_no(rung)} must be the last element of its branch, "
                f"but {node_text(items[position + 1])} follows it",
                item.span,
            ))
    return found
