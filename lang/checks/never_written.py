"""LD131: a variable that is read but never written."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import label, read_never_written, rung_no

CODE = register(
    "LD131", "variable read but never written",
    "A variable (or output, timer, counter, A/D reading) that instructions read but that no "
    "instruction ever writes keeps its start value 0, which is usually a misspelt name. LDmicro's "
    "simulator stops on it: \"Variable '...' not assigned to, e.g. with a MOV statement, an ADD "
    "statement, etc.\" Inputs (X), Modbus inputs and registers (I, M, H, written from outside), "
    "hardware registers (#) and compiler names ($) are exempt; internal relays have LD130.",
)

_EXEMPT = ("X", "I", "M", "H", "R", "$", "#")


def check(program, index):
    found = []
    for name, first_read in read_never_written(index):
        if name.startswith(_EXEMPT):
            continue
        found.append(warning(
            CODE,
            f"'{name}' is read by {label(first_read.element)} in {rung_no(first_read.rung)} "
            "but nothing ever writes it: it is always 0",
            first_read.span,
        ))
    return found
