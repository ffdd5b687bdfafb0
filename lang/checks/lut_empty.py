"""LD308: a look-up table with no values."""

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
    for rung, element in index.of_kind("LOOK_UP_TABLE"):
        if not element.args.get("values"):
            table = token(element.args.get("table"))
            name = f" '{table}'" if table else ""
            found.append(report(CODE, f"LUT table{name} in {rung_no(rung)} has no values", element.span))
    return found
