"""LD303: a constant where a variable must be written."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import INSTRUCTIONS
from ..labels import label
from ..model import Program
from .common import RUNGS, arg_span, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS

# (kind, field) of every operand an instruction writes
_WRITES = frozenset(
    (key, f.name)
    for key, spec in INSTRUCTIONS.items()
    for f in spec.fields
    if f.kind in ("var", "bit") and f.access in ("write", "rw")
)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return [
        report(
            CODE,
            f"{label(literal.element)} in {rung_no(literal.rung)}: '{literal.text}' is not a valid "
            f"destination; the {literal.field} must be a variable",
            arg_span(literal.element, literal.field),
        )
        for literal in index.literals
        if (literal.element.kind, literal.field) in _WRITES
    ]
