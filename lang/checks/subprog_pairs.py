"""LD205: a SUBPROG without its ENDSUB, or an ENDSUB without its SUBPROG."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Program
from .common import arg_span, rung_no

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    starts: dict[str, int] = {}
    for rung, element in index.of_kind("SUBPROG"):
        starts.setdefault(token(element.args.get("label")), rung)
    ends: dict[str, int] = {}
    for rung, element in index.of_kind("ENDSUB"):
        name = token(element.args.get("label"))
        ends[name] = max(ends.get(name, rung), rung)
        if name not in starts or starts[name] > rung:
            found.append(report(
                CODE,
                f"ENDSUB '{name}' in {rung_no(rung)} has no SUBPROG '{name}' before it",
                arg_span(element, "label"),
            ))
    for rung, element in index.of_kind("SUBPROG"):
        name = token(element.args.get("label"))
        if starts.get(name) != rung:
            continue  # a duplicate: LD206
        if name not in ends or ends[name] < rung:
            found.append(report(
                CODE,
                f"SUBPROG '{name}' in {rung_no(rung)} has no ENDSUB '{name}' after it",
                arg_span(element, "label"),
            ))
    return found
