"""LD208: GOSUB to a SUBPROG that does not exist."""

from __future__ import annotations

from difflib import get_close_matches

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import arg_span, rung_no

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    subs = {token(e.args.get("label")) for _, e in index.of_kind("SUBPROG")}
    for rung, element in index.of_kind("GOSUB"):
        name = token(element.args.get("label"))
        if name.isdigit() or name in subs:
            continue  # a number is LD209
        close = get_close_matches(name, subs, n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        found.append(report(
            CODE,
            f"GOSUB '{name}' in {rung_no(rung)}: there is no SUBPROG '{name}'{hint}",
            arg_span(element, "label"),
        ))
    return found
