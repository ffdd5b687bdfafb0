"""LD101: a contact on a name that is not a bit."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import RUNGS, arg_span, prefix_fixes, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS

_ALLOWED = "XYRPIM"


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("CONTACTS"):
        name = token(element.args.get("name"))
        if not name or name[0] in _ALLOWED:
            continue
        if name[0] in "TCA":
            what = {"T": "a timer", "C": "a counter", "A": "an A/D reading"}[name[0]]
            hint = f"'{name}' is {what}, an integer; compare it (e.g. GRT/EQU) instead"
        else:
            hint = f"'{name}' is an integer variable; test it with a comparison or IF BIT SET"
        found.append(report(
            CODE,
            f"contact '{name}' in {rung_no(rung)} must name a bit (X, Y, R, P, I or M): {hint}",
            arg_span(element, "name"),
            fixes=prefix_fixes(index, element, "name"),
        ))
    return found
