"""LD309: a look-up table with more than 64 values."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import RUNGS, arg_span, rung_no, table_of

CODE = rule_code(__name__)
SCOPE = RUNGS

LIMIT = 64


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("LOOK_UP_TABLE"):
        count = len(table_of(element, "values"))
        if count > LIMIT:
            table = token(element.args.get("table"))
            name = f" '{table}'" if table else ""
            found.append(report(
                CODE,
                f"LUT table{name} in {rung_no(rung)} has {count} values; at most {LIMIT} are allowed",
                arg_span(element, "values"),
            ))
    return found
