"""LD710: an operand form no code is written for (a negative DELAY, a variable
where a constant time is needed, a PWM resolution or UART byte count the
instruction does not have, a bit name where an integer variable is needed),
on a program about to be compiled: for a part a back end compiles, or to C."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from ..semantics.operands import REFUSALS, bit_refusal, integer_operand, operand_refusal
from ..storage import BIT_FIELDS, OVERFLOW, bit_operand
from ..targets import compiled
from .common import variable_of_uses

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


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if index.family is None and (device is None or not compiled(device)):
        return []
    found = []
    for _, element in index.of_kind(*REFUSALS):
        refused = operand_refusal(element, lambda name: variable_of_uses(program, index, name)[1])
        if refused:
            found.append(report(CODE, refused, element.span))
    for name, uses in index.uses.items():
        if not _a_bit(name, uses):
            continue
        # the lowering refuses a bit at the first element that needs it as an integer
        first = next((use for use in uses if integer_operand(use.element, use.field)), None)
        if first is not None:
            found.append(report(CODE, bit_refusal(name), first.element.span))
    return found
