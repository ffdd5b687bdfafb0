"""LD121: a timer on a name that an earlier instruction already used."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, mark_related, mark_text, rung_no
from .varflags import analyse

CODE = register(
    "LD121", "timer on a name already used by another instruction",
    "A timer's name may be used elsewhere only by RES. LDmicro walks the program in order and "
    "refuses a timer whose name an earlier instruction (a MOV, a counter, a table, a label...) "
    "already used: \"TON: variable can only be used for RES elsewhere\". The check is order "
    "dependent: the same MOV placed after an RTO is accepted (see LD122).",
)


def check(program, index):
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "timer-other":
            continue
        mark = conflict.mark
        found.append(error(
            CODE,
            f"{mark.flag} '{mark.name}' in {rung_no(mark.rung)}: the name is already used by "
            f"{mark_text(conflict.earlier[0])}; a timer's name can only be used elsewhere by RES",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
