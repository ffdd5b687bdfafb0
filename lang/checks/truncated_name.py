"""LD010: a name LDmicro's text export cut with `~`."""

from __future__ import annotations

from ..codes import TRUNCATED
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import INSTRUCTIONS
from ..labels import label
from ..model import Program
from .common import PROGRAM, RUNGS, arg_span, rung_no

CODE = TRUNCATED  # registered in lang.codes: the readers know it too

# operands the index does not record as names or constants (labels, table names, bus names...)
_OTHER_FIELDS = {
    key: tuple(f.name for f in spec.fields if f.kind in ("label", "token"))
    for key, spec in INSTRUCTIONS.items()
}
_OTHER_FIELDS["SHIFT_REGISTER"] += ("name",)  # the index records its stages, not the name
_OTHER_FIELDS = {key: fields for key, fields in _OTHER_FIELDS.items() if fields}


def _error(value: str, rung: int, element, field: str):
    return report(
        CODE,
        f"'{value}' ({label(element)}, {rung_no(rung)}) is a name LDmicro's text export cut short "
        "with '~': the full name is lost; write the whole name (it is in the .ld file)",
        arg_span(element, field),
    )


def check_rungs(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, uses in index.uses.items():
        if name.endswith("~"):
            for use in uses:
                if use.field != "table":  # the table name is reported below with the other tokens
                    found.append(_error(name, use.rung, use.element, use.field))
    for literal in index.literals:
        if literal.text.endswith("~"):
            found.append(_error(literal.text, literal.rung, literal.element, literal.field))
    for kind, fields in _OTHER_FIELDS.items():
        for rung, element in index.by_kind.get(kind, ()):
            for field in fields:
                value = element.args.get(field)
                if isinstance(value, str) and value.endswith("~"):
                    found.append(_error(value, rung, element, field))
    return found


def check_table(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """The I/O table's rows, apart: RUNGS rules never read the pins."""
    found = []
    for name, assignment in program.pins.items():
        if name.endswith("~"):
            found.append(report(
                CODE,
                f"'{name}' in the I/O assignment is a name LDmicro's text export cut short with '~': "
                "write the whole name",
                assignment.span,
            ))
    return found


CHECKS = {RUNGS: check_rungs, PROGRAM: check_table}
