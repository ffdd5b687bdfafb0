"""LD210: two LABELs of one name."""

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
    first: dict[str, tuple[int, Element]] = {}
    for rung, element in index.of_kind("LABEL"):
        name = token(element.args.get("label"))
        if name not in first:
            first[name] = (rung, element)
            continue
        first_rung, first_element = first[name]
        span = arg_span(first_element, "label")
        related = [Related(span, f"the first LABEL '{name}'")] if span else []
        found.append(report(
            CODE,
            f"LABEL '{name}' in {rung_no(rung)}: there is already a LABEL '{name}' in {rung_no(first_rung)}",
            arg_span(element, "label"),
            *related,
        ))
    return found
