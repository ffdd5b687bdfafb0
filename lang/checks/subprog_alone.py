"""LD204: SUBPROG or ENDSUB that shares its rung with other elements."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import RUNGS, arg_span, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("SUBPROG", "ENDSUB"):
        items = program.rungs[rung].circuit.items
        if len(items) == 1 and items[0] is element:
            continue
        name = token(element.args.get("label"))
        found.append(report(
            CODE,
            f"{element.kind} '{name}' in {rung_no(rung)} must be the only element of its rung",
            element.span or arg_span(element, "label"),
        ))
    return found
