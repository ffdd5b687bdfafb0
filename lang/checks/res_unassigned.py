"""LD125: RES on a name no timer, counter or PWM output uses."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no
from .varflags import analyse

CODE = register(
    "LD125", "RES on a name that is no timer, counter or PWM output",
    "RES resets the timer, counter or PWM output of its name. When nothing else in the program "
    "gives the name a value (no timer, counter, SET PWM or other instruction writes it), LDmicro "
    "refuses to compile: \"RES: Variable is not assigned to COUNTER or TIMER or PWM. You must "
    "assign a variable.\" Usually the name is misspelt.",
)


def check(program, index):
    found = []
    for mark in analyse(index).res_only:
        found.append(error(
            CODE,
            f"RES '{mark.name}' in {rung_no(mark.rung)}: no timer, counter or PWM output is named "
            f"'{mark.name}' (is the name misspelt?)",
            arg_span(mark.element, mark.field),
        ))
    return found
