"""LD207: GOTO to a LABEL that does not exist."""

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
    labels = {token(e.args.get("label")) for _, e in index.of_kind("LABEL")}
    for rung, element in index.of_kind("GOTO"):
        name = token(element.args.get("label"))
        if name.isdigit() or name in labels:
            continue  # a rung number (LDmicro clamps it) or a known label
        close = get_close_matches(name, labels, n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        found.append(report(
            CODE,
            f"GOTO '{name}' in {rung_no(rung)}: there is no LABEL '{name}'{hint}",
            arg_span(element, "label"),
        ))
    return found
