"""LD301: a constant that does not fit the variable it is stored in or compared with."""

from __future__ import annotations

from functools import lru_cache

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import COUNTERS, RELATIONS
from ..labels import label, token
from ..model import Program
from ..values import is_literal
from .common import RUNGS, arg_span, fits, is_decimal, literal_or_none, range_text, rung_no, var_size

CODE = rule_code(__name__)
SCOPE = RUNGS

# (kind, constant's field) -> (the field naming the variable it must fit, its role)
_TARGETS: dict[tuple[str, str], tuple[str, str]] = {("MOVE", "src"): ("dest", "source")}
for _kind in ("ADD", "SUB", "MUL", "DIV", "MOD", "AND", "OR", "XOR"):
    _TARGETS[(_kind, "op1")] = ("dest", "operand")
    _TARGETS[(_kind, "op2")] = ("dest", "operand")
for _kind in ("NEG", "NOT", "SHL", "SHR", "SR0", "ROL", "ROR"):
    _TARGETS[(_kind, "op1")] = ("dest", "operand")  # a shift count (op2) is LD302
for _kind in RELATIONS:
    _TARGETS[(_kind, "op1")] = ("op2", "operand")
    _TARGETS[(_kind, "op2")] = ("op1", "operand")
for _kind in COUNTERS:
    _TARGETS[(_kind, "max")] = ("name", "limit")
    _TARGETS[(_kind, "init")] = ("name", "start value")


@lru_cache(maxsize=4096)
def _outside(text: str, size: int) -> str | None:
    """The range a constant misses for a variable of `size` bytes, or None
    when it fits (or is malformed: LD304 reports those)."""
    value = literal_or_none(text)
    if value is None:
        return None
    decimal = is_decimal(text)
    return None if fits(value, size, decimal) else range_text(size, decimal)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for literal in index.literals:
        target = _TARGETS.get((literal.element.kind, literal.field))
        if target is None:
            continue
        field, role = target
        name = token(literal.element.args.get(field))
        if not name or is_literal(name) or name.startswith(("#", "$")):
            continue
        size = var_size(program, name)
        if size is None:
            continue
        allowed = _outside(literal.text, size)
        if allowed is None:
            continue
        found.append(report(
            CODE,
            f"constant {literal.text} ({label(literal.element)} {role}, {rung_no(literal.rung)}) does not "
            f"fit '{name}', a {size}-byte variable: {allowed}",
            arg_span(literal.element, literal.field),
        ))
    return found
