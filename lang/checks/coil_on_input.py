"""LD102: a coil (or set/reset/toggle coil) writing an X input."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label, token
from ..model import Program
from .common import RUNGS, arg_span, prefix_fixes, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("COIL"):
        name = token(element.args.get("name"))
        if name.startswith("X"):
            found.append(report(
                CODE,
                f"{label(element)} '{name}' in {rung_no(rung)} writes an input pin: "
                "X names can only be read; write an output (Y) or a relay (R)",
                arg_span(element, "name"),
                fixes=prefix_fixes(index, element, "name"),
            ))
    return found
