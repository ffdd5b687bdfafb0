"""LD123: SET PWM on a name an earlier instruction already used otherwise."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, mark_related, mark_text, rung_no
from .varflags import analyse

CODE = register(
    "LD123", "PWM output name already used otherwise",
    "A PWM output's name may be used elsewhere only by RES (which switches it off) and by other "
    "SET PWM instructions. LDmicro refuses a SET PWM whose name an earlier instruction (a timer, a "
    "counter, a MOV...) already used: \"PWM: variable can only be used for RES elsewhere\".",
)


def check(program, index):
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "pwm":
            continue
        mark = conflict.mark
        found.append(error(
            CODE,
            f"SET PWM '{mark.name}' in {rung_no(mark.rung)}: the name is already used by "
            f"{mark_text(conflict.earlier[0])}; a PWM output's name can only be used elsewhere by RES",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
