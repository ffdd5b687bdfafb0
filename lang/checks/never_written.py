"""LD131: a variable that is read but never written."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from .common import NAMES, read_never_written, rung_no

CODE = rule_code(__name__)
SCOPE = NAMES

_EXEMPT = ("X", "I", "M", "H", "R", "$", "#")


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, first_read in read_never_written(index):
        if name.startswith(_EXEMPT):
            continue
        found.append(report(
            CODE,
            f"'{name}' is read by {label(first_read.element)} in {rung_no(first_read.rung)} "
            "but nothing ever writes it: it is always 0",
            first_read.span,
        ))
    return found
