"""LD316: a comparison that always gives the same result, from its constants
and the values its variables can hold (lang.checks.ranges)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import RELATIONS
from ..labels import token
from ..model import Element, Program
from ..values import is_literal
from .common import NAMES, RUNGS, rung_no
from .ranges import comparison_result, reading, values_of

CODE = rule_code(__name__)


def _diagnostic(program: Program, index: ProgramIndex, rung: int, element: Element) -> Diagnostic | None:
    result = comparison_result(program, index, element)
    if result is None:
        return None
    op1, op2 = token(element.args.get("op1")), token(element.args.get("op2"))
    why = [_why(program, index, name) for name in (op1, op2) if not is_literal(name)]
    reason = "; ".join(why) if why else "both operands are constants"
    return report(
        CODE,
        f"{element.kind} [{op1} {RELATIONS[element.kind]} {op2}] in {rung_no(rung)} is always "
        f"{'true' if result else 'false'}: {reason}",
        element.span,
    )


def _why(program: Program, index: ProgramIndex, name: str) -> str:
    values = values_of(program, index, name)
    assert values is not None  # comparison_result gave a result
    if values.exact is not None:
        held = ", ".join(str(v) for v in sorted(values.exact))
        return f"'{name}' only ever holds {held} (its start value 0 and the constants MOV writes)"
    return f"'{name}' holds {values.low} to {values.high}"


def check_constants(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """Comparisons of two constants: a function of their rung alone."""
    found = []
    for rung, element in index.of_kind(*RELATIONS):
        if is_literal(token(element.args.get("op1"))) and is_literal(token(element.args.get("op2"))):
            diagnostic = _diagnostic(program, index, rung, element)
            if diagnostic is not None:
                found.append(diagnostic)
    return found


def check_names(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    """Comparisons with a variable: a function of their operands' uses."""
    found = []
    for rung, element in reading(index, tuple(RELATIONS), ("op1", "op2")):
        diagnostic = _diagnostic(program, index, rung, element)
        if diagnostic is not None:
            found.append(diagnostic)
    return found


CHECKS = {RUNGS: check_constants, NAMES: check_names}
