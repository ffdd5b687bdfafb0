"""LD710: an operand form no code is written for (a negative DELAY, a variable
where a constant time is needed, a PWM resolution or UART byte count the
instruction does not have), on a program about to be compiled: for a part a
back end compiles, or to C."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from ..semantics.operands import REFUSALS, operand_refusal
from ..targets import compiled
from .common import variable_of_uses

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if index.family is None and (device is None or not compiled(device)):
        return []
    found = []
    for _, element in index.of_kind(*REFUSALS):
        refused = operand_refusal(element, lambda name: variable_of_uses(program, index, name)[1])
        if refused:
            found.append(report(CODE, refused, element.span))
    return found
