"""LD130: an internal relay that is read but never written."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from .common import NAMES, read_never_written, rung_no

CODE = rule_code(__name__)
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, first_read in read_never_written(index):
        if not name.startswith("R"):
            continue
        found.append(report(
            CODE,
            f"internal relay '{name}' is read by {label(first_read.element)} in "
            f"{rung_no(first_read.rung)} but no coil ever writes it: it is always 0",
            first_read.span,
        ))
    return found
