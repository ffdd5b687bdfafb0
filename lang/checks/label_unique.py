"""LD210: two LABELs of one name."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import Related, error
from .common import arg_span, rung_no, token

CODE = register(
    "LD210", "duplicate LABEL",
    "A LABEL name marks one rung as a GOTO target, so it must be unique. LDmicro: \"LABEL: Only one "
    "LABEL '...' is allowed!\".",
)


def check(program, index):
    found = []
    first: dict[str, tuple[int, object]] = {}
    for rung, element in index.of_kind("LABEL"):
        name = token(element.args.get("label"))
        if name not in first:
            first[name] = (rung, element)
            continue
        first_rung, first_element = first[name]
        span = arg_span(first_element, "label")
        related = [Related(span, f"the first LABEL '{name}'")] if span else []
        found.append(error(
            CODE,
            f"LABEL '{name}' in {rung_no(rung)}: there is already a LABEL '{name}' in {rung_no(first_rung)}",
            arg_span(element, "label"),
            *related,
        ))
    return found
