"""LD302: a shift or rotate count outside 0..8*size."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from ..values import is_literal
from .common import RUNGS, arg_span, literal_or_none, rung_no, var_size

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for rung, element in index.of_kind("SHL", "SHR", "SR0", "ROL", "ROR"):
        count = literal_or_none(token(element.args.get("op2")))
        if count is None:
            continue
        source = token(element.args.get("op1"))
        if not source or is_literal(source):
            source = token(element.args.get("dest"))
        size = var_size(program, source)
        if size is None or 0 <= count <= 8 * size:
            continue
        found.append(report(
            CODE,
            f"{element.kind} in {rung_no(rung)}: shift count {count} is out of range for '{source}' "
            f"({size} bytes): 0 to {8 * size} inclusive",
            arg_span(element, "op2"),
        ))
    return found
