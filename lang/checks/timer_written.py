"""LD122: a timer's or PWM output's name written by a general instruction after it."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, label, mark_related, mark_text, rung_no
from .varflags import PWM, analyse

CODE = register(
    "LD122", "timer or PWM name written by another instruction",
    "After a TON, TOF, TCY, RTL, THI, TLO or SET PWM, LDmicro refuses any general instruction that "
    "writes the same name (MOV, arithmetic, READ ADC, a LUT destination, a label of that name...): "
    "the timer's count or the PWM state would be overwritten. RTO is the exception: writing an RTO's "
    "count after it is accepted, and so are counters. Reads (comparisons) are always fine.",
)


def check(program, index):
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "written":
            continue
        mark = conflict.mark
        owner = conflict.earlier[0]
        what = "PWM" if owner.flag == PWM else owner.flag
        found.append(error(
            CODE,
            f"{label(mark.element)} in {rung_no(mark.rung)} uses '{mark.name}', which is "
            f"{mark_text(owner)}; that name can only be used elsewhere by RES "
            f"({what}: variable can only be used for RES elsewhere)",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
