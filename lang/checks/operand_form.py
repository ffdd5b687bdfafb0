"""LD710: an operand form no code is written for (a negative DELAY, a variable
where a constant time is needed, a PWM resolution or UART byte count the
instruction does not have, a bit name where an integer variable is needed),
on a program about to be compiled: for a part a back end compiles, or to C."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex, shift_register_names
from ..model import Program
from ..semantics.operands import INTEGER_FIELDS_OF, REFUSALS, bit_refusal, integer_operand, operand_refusal
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


def _in_integer_fields(index: ProgramIndex) -> set[str]:
    """The names held in an operand `integer_operand` may accept: a superset
    of those it accepts, gathered from the elements of those instructions
    alone, so that an edit does not scan every use of every name."""
    found: set[str] = set()
    by_kind = index.by_kind
    for kind, fields in INTEGER_FIELDS_OF.items():
        for _, element in by_kind.get(kind, ()):
            if kind == "SHIFT_REGISTER":
                found.update(name for name, _, _ in shift_register_names(element))
                continue
            args = element.args
            found.update(value for value in map(args.get, fields) if isinstance(value, str))
    return found


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if index.family is None and (device is None or not compiled(device)):
        return []
    found = []
    for _, element in index.of_kind(*REFUSALS):
        refused = operand_refusal(element, lambda name: variable_of_uses(program, index, name)[1])
        if refused:
            found.append(report(CODE, refused, element.span))
    candidates = _in_integer_fields(index)
    for name, uses in index.uses.items():
        if name not in candidates or not _a_bit(name, uses):
            continue
        # the lowering refuses a bit at the first element that needs it as an integer
        first = next((use for use in uses if integer_operand(use.element, use.field)), None)
        if first is not None:
            found.append(report(CODE, bit_refusal(name), first.element.span))
    return found
