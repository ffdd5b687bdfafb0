"""LD206: two SUBPROG (or two ENDSUB) of one name."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex
from ..labels import token
from ..model import Element, Program
from .common import arg_span, rung_no

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for kind in ("SUBPROG", "ENDSUB"):
        first: dict[str, tuple[int, Element]] = {}
        for rung, element in index.of_kind(kind):
            name = token(element.args.get("label"))
            if name not in first:
                first[name] = (rung, element)
                continue
            first_rung, first_element = first[name]
            span = arg_span(first_element, "label")
            related = [Related(span, f"the first {kind} '{name}'")] if span else []
            found.append(report(
                CODE,
                f"{kind} '{name}' in {rung_no(rung)}: there is already a {kind} '{name}' in "
                f"{rung_no(first_rung)}; only one is allowed",
                arg_span(element, "label"),
                *related,
            ))
    return found
