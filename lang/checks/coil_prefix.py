"""LD103: a coil on a name that is not Y, R or M (X has its own rule, LD102)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label, token
from ..model import Program
from ..values import is_literal
from .common import RUNGS, arg_span, prefix_fixes, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("COIL"):
        name = token(element.args.get("name"))
        if not name or is_literal(name) or name[0] in "YRMX":
            continue
        found.append(report(
            CODE,
            f"{label(element)} '{name}' in {rung_no(rung)} must name an output bit "
            "(Y output, R relay or M Modbus coil)",
            arg_span(element, "name"),
            fixes=prefix_fixes(index, element, "name"),
        ))
    return found
