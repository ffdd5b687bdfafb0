"""LD317: a DIV or MOD whose divisor can be 0 (the simulator stops there,
LD610; the MCU's result is undefined), from the values the divisor can hold
(lang.checks.ranges) and the comparisons that guard it in its rung."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex
from ..instructions import RELATIONS
from ..labels import label, token
from ..model import Element, Parallel, Program, Series
from .common import NAMES, RUNGS, arg_span, literal_or_none, rung_no
from .ranges import Values, compare, reading, values_of

CODE = rule_code(__name__)
DIVISIONS = ("DIV", "MOD")
ZERO = Values.of(frozenset((0,)))


def check_constants(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """A divisor written as the constant 0: a function of its rung alone."""
    return [report(CODE, f"{element.kind} in {rung_no(rung)} divides by the constant 0 whenever its rung is true",
                   arg_span(element, "op2"))
            for rung, element in index.of_kind(*DIVISIONS)
            if literal_or_none(token(element.args.get("op2"))) == 0]


def check_names(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """A divisor variable that can hold 0 where its rung does not rule 0 out:
    a function of the divisor's uses (its writes, and its rung through it)."""
    found = []
    for rung, element in reading(index, DIVISIONS, ("op2",)):
        name = token(element.args.get("op2"))
        values = values_of(program, index, name)
        if values is None or _guarded(program.rungs[rung].circuit, element, name):
            continue
        why = _zero_why(index, element, name, values)
        if why is not None:
            found.append(report(
                CODE, f"{element.kind} in {rung_no(rung)} divides by '{name}', which can be 0: {why[0]}; "
                      f"test it first (NEQ {name} 0 before the {element.kind} in the rung)",
                arg_span(element, "op2"), *why[1]))
    return found


def _zero_why(index: ProgramIndex, division: Element, name: str,
              values: Values) -> tuple[str, tuple[Related, ...]] | None:
    """How the divisor can be 0 (and where it is written so), or None."""
    if values.assigned is None:
        assert values.writer is not None
        where, writer = values.writer
        related = (Related(writer.span, f"'{name}' written here"),) if writer.span is not None else ()
        return f"the {label(writer)} in {rung_no(where)} can leave any value in it, 0 included", related
    if 0 in values.assigned:
        return f"a MOV sets '{name}' to 0", ()
    # only non-zero constants: 0 only before the first of them, the variable's start value
    for use in index.names.get(name, ()):
        if use.element is division:
            return f"it starts at 0 and no MOV sets it before this {division.kind} in the scan", ()
        if use.writes:
            return None  # a MOV comes first in the scan: set before the first division
    return None


def _guarded(circuit: Series, target: Element, name: str) -> bool:
    """A comparison in series before `target`, on its way through the rung,
    fails for `name` = 0: `target` never gets power with a zero divisor."""
    # (node, whether a guard comes before it), walked without recursion: rungs nest deep
    pending: list[tuple[object, bool]] = [(circuit, False)]
    while pending:
        node, guarded = pending.pop()
        if node is target:
            return guarded
        if isinstance(node, Series):
            for item in node.items:
                pending.append((item, guarded))
                guarded = guarded or (isinstance(item, Element) and item.kind in RELATIONS
                                      and _excludes_zero(item, name))
        elif isinstance(node, Parallel):
            pending.extend((branch, guarded) for branch in node.branches)
    return False


def _excludes_zero(element: Element, name: str) -> bool:
    op1, op2 = token(element.args.get("op1")), token(element.args.get("op2"))
    if name not in (op1, op2) or op1 == op2:
        return False
    constant = literal_or_none(op2 if op1 == name else op1)
    if constant is None:
        return False
    fixed = Values.of(frozenset((constant,)))
    operands = (ZERO, fixed) if op1 == name else (fixed, ZERO)
    return compare(element.kind, *operands) is False


CHECKS = {RUNGS: check_constants, NAMES: check_names}
