"""LD212: an empty rung."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("PLACEHOLDER"):
        found.append(report(
            CODE,
            f"{rung_no(rung)} is empty; delete it or add instructions",
            element.span or program.rungs[rung].span,
        ))
    return found
