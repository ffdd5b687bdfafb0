"""LD201: an end-of-line instruction that is not the last of its branch."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from ..model import Element
from .common import describe, node_text, rung_no

CODE = register(
    "LD201", "end-of-line instruction not last in its branch",
    "Coils, RES, MOV, ADD, SUB, MUL, DIV, MOD, READ ADC, SET PWM, MASTER RLY, GOTO, GOSUB, RETURN, "
    "SHIFT REG, LUT, PWL, PERSIST and the other end-of-line instructions must be the last element "
    "of their branch: they produce no rung state for anything to their right. LDmicro's editor "
    "never draws anything after them. Put the following elements in a branch of their own.",
)


def check(program, index):
    found = []
    for rung, series, position in index.followed:
        items = series.items
        item = items[position]
        if item.__class__ is Element:
            found.append(error(
                CODE,
                f"{describe(item)} in {rung_no(rung)} must be the last element of its branch, "
                f"but {node_text(items[position + 1])} follows it",
                item.span,
            ))
    return found
