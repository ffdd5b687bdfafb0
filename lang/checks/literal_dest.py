"""LD303: a constant where a variable must be written."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from ..instructions import INSTRUCTIONS
from .common import arg_span, label, rung_no

CODE = register(
    "LD303", "constant as a destination",
    "The destination of MOV, arithmetic, BIN2BCD, SWAP, SRAND, the segment decoders and every "
    "other operand an instruction writes must be a variable, not a number. LDmicro: \"Move "
    "instruction: '5' not a valid destination.\" (and the same for the other instructions).",
)

# (kind, field) of every operand an instruction writes
_WRITES = frozenset(
    (key, f.name)
    for key, spec in INSTRUCTIONS.items()
    for f in spec.fields
    if (f.kind in ("var", "bit") and f.access in ("write", "rw")) or (key == "RSFR" and f.name == "dest")
)


def check(program, index):
    return [
        error(
            CODE,
            f"{label(literal.element)} in {rung_no(literal.rung)}: '{literal.text}' is not a valid "
            f"destination; the {literal.field} must be a variable",
            arg_span(literal.element, literal.field),
        )
        for literal in index.literals
        if (literal.element.kind, literal.field) in _WRITES
    ]
