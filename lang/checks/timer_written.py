"""LD122: a timer's or PWM output's name written by a general instruction after it."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from .common import NAMES, arg_span, mark_related, mark_text, rung_no
from .varflags import PWM, analyse

CODE = rule_code(__name__)
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "written":
            continue
        mark = conflict.mark
        owner = conflict.earlier[0]
        what = "PWM" if owner.flag == PWM else owner.flag
        found.append(report(
            CODE,
            f"{label(mark.element)} in {rung_no(mark.rung)} uses '{mark.name}', which is "
            f"{mark_text(owner)}; that name can only be used elsewhere by RES "
            f"({what}: variable can only be used for RES elsewhere)",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
