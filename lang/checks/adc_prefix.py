"""LD109: READ ADC into a name that does not start with A."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from ..values import is_literal
from .common import RUNGS, arg_span, prefix_fixes, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("READ_ADC"):
        name = token(element.args.get("name"))
        if name and not is_literal(name) and not name.startswith("A"):
            found.append(report(
                CODE,
                f"READ ADC '{name}' in {rung_no(rung)}: A/D input names start with A (e.g. 'A{name}')",
                arg_span(element, "name"),
                fixes=prefix_fixes(index, element, "name"),
            ))
    return found
