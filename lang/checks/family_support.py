"""LD501: an instruction the selected part's family (or the family the program
is compiled for, as C) cannot compile.

A warning while editing and in `ladder check` (the program can still be
simulated), an error when the program is compiled (`ladder build`, compile on
save): the caller chooses, through `ProgramIndex.for_build`.
"""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import ERROR, Diagnostic, report
from ..families import FAMILIES, Family, family_of
from ..index import ProgramIndex
from ..instructions import INSTRUCTIONS
from ..labels import describe
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    family: Family | None
    if index.family is not None:
        family = FAMILIES[index.family]
        what = f"{family.title} output"
    else:
        family = family_of(device) if device is not None else None
        what = device.title if device is not None else ""
    if family is None:
        return []
    severity = ERROR if index.for_build else None
    found = []
    for kind, elements in index.by_kind.items():
        if kind == "PLACEHOLDER":
            continue  # an empty rung is LD212
        spec = INSTRUCTIONS.get(kind)
        if spec is None or spec.supports(family.key):
            continue
        for rung, element in elements:
            found.append(report(
                CODE,
                f"{describe(element)} in {rung_no(rung)} cannot be compiled for the {what}: "
                f"the {family.title} back end does not support it",
                element.span,
                severity=severity,
            ))
    return found
