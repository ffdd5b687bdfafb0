"""LD710: an operand form no code is written for (a negative DELAY, a variable
where a constant time is needed, a PWM resolution or UART byte count the
instruction does not have, a bit name where an integer variable is needed),
on a program about to be compiled: for a part a back end compiles, or to C."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..families import compiled
from ..index import ProgramIndex
from ..model import Program
from ..semantics.operands import REFUSALS, bit_refusal, integer_operand, operand_refusal
from ..storage import BIT_FIELDS, OVERFLOW, bit_operand
from .common import NAMES, PROGRAM, variable_of_uses

CODE = rule_code(__name__)


def _a_bit(name: str, uses) -> bool:
    """Whether the lowering makes the name a bit (lang.storage.bit_operand), the
    common operands looked up first: every edit asks it of every name."""
    if name == OVERFLOW:
        return True
    for use in uses:
        if (use.element.kind, use.field) in BIT_FIELDS:
            return True
    return name[:1] == "P" and any(bit_operand(use.element, use.field) for use in uses)


def check_operands(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """The forms an instruction refuses, some of them by another name's size."""
    if not _compiled(index):
        return []
    found = []
    for _, element in index.of_kind(*REFUSALS):
        refused = operand_refusal(element, lambda name: variable_of_uses(program, index, name)[1])
        if refused:
            found.append(report(CODE, refused, element.span))
    return found


def check_bits(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """A bit where an integer variable is needed: a function of the name's
    uses alone, so an edit checks again only the names it touched."""
    if not _compiled(index):
        return []
    found = []
    for name, uses in index.uses.items():
        if not _a_bit(name, uses):
            continue
        # the lowering refuses a bit at the first element that needs it as an integer
        first = next((use for use in uses if integer_operand(use.element, use.field)), None)
        if first is not None:
            found.append(report(CODE, bit_refusal(name), first.element.span))
    return found


def _compiled(index: ProgramIndex) -> bool:
    device = index.device
    return index.family is not None or (device is not None and compiled(device))


CHECKS = {PROGRAM: check_operands, NAMES: check_bits}
