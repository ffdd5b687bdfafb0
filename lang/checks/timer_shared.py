"""LD120: two timers with one name (LDmicro's CheckVariableNames)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import NAMES, arg_span, mark_related, mark_text, rung_no
from .varflags import analyse

CODE = rule_code(__name__)
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "timer-timer":
            continue
        mark = conflict.mark
        first = conflict.earlier[0]
        same = " also" if first.flag == mark.flag else ""
        found.append(report(
            CODE,
            f"{mark.flag} '{mark.name}' in {rung_no(mark.rung)}: the name is{same} {mark_text(first)}; "
            f"each timer needs its own name ({mark.flag}: variable can only be used for RES elsewhere)",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
