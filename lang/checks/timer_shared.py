"""LD120: two timers with one name (LDmicro's CheckVariableNames)."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, mark_related, mark_text, rung_no
from .varflags import analyse

CODE = register(
    "LD120", "two timers share a name",
    "Each timer keeps its count in the variable it is named after, so two timers (TON, TOF, RTO, "
    "RTL, TCY, THI, TLO, of the same or of different kinds) cannot have the same name: they would "
    "disturb each other's count. Only RES may use a timer's name elsewhere (and, after the timer, "
    "general instructions may read or write an RTO's count). LDmicro reports \"TON: variable can "
    "only be used for RES elsewhere\" at the second timer, in program order.",
)


def check(program, index):
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "timer-timer":
            continue
        mark = conflict.mark
        first = conflict.earlier[0]
        same = " also" if first.flag == mark.flag else ""
        found.append(error(
            CODE,
            f"{mark.flag} '{mark.name}' in {rung_no(mark.rung)}: the name is{same} {mark_text(first)}; "
            f"each timer needs its own name ({mark.flag}: variable can only be used for RES elsewhere)",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
