"""LD304: a malformed constant (a bad character literal, a number with stray characters)."""

from __future__ import annotations

from functools import lru_cache

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from ..values import is_literal, literal_value
from .common import RUNGS, arg_span, rung_no, table_of

CODE = rule_code(__name__)
SCOPE = RUNGS


@lru_cache(maxsize=4096)
def _problem(text: str) -> str | None:
    """Why a constant is malformed, or None."""
    if text.endswith("~"):
        return None  # a value LDmicro's export cut: LD010
    try:
        literal_value(text)
    except ValueError as exc:
        return str(exc)
    return None


def _table_problem(value) -> str | None:
    if isinstance(value, int):
        return None
    text = str(value)
    if text.endswith("~"):
        return None
    if not is_literal(text):
        return f"'{text}' is not a number (table entries must be constants)"
    return _problem(text)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for literal in index.literals:
        reason = _problem(literal.text)
        if reason:
            found.append(report(
                CODE,
                f"malformed constant in {label(literal.element)}, {rung_no(literal.rung)}: {reason}",
                arg_span(literal.element, literal.field),
            ))
    for rung, element in index.of_kind("LOOK_UP_TABLE"):
        for position, value in enumerate(table_of(element, "values")):
            reason = _table_problem(value)
            if reason:
                found.append(report(
                    CODE,
                    f"LUT in {rung_no(rung)}, entry {position}: {reason}",
                    arg_span(element, "values"),
                ))
    for rung, element in index.of_kind("PIECEWISE_LINEAR"):
        for position, point in enumerate(table_of(element, "points")):
            for axis, value in zip("xy", point):
                reason = _table_problem(value)
                if reason:
                    found.append(report(
                        CODE,
                        f"PWL in {rung_no(rung)}, point {position} {axis}: {reason}",
                        arg_span(element, "points"),
                    ))
    return found
