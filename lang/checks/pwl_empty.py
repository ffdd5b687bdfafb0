"""LD305: a piecewise-linear table with no points."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("PIECEWISE_LINEAR"):
        if not element.args.get("points"):
            table = token(element.args.get("table"))
            name = f" '{table}'" if table else ""
            found.append(report(
                CODE,
                f"PWL table{name} in {rung_no(rung)} has no points",
                element.span,
            ))
    return found
