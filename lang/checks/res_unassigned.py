"""LD125: RES on a name no timer, counter or PWM output uses."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import NAMES, arg_span, rung_no
from .varflags import analyse

CODE = rule_code(__name__)
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for mark in analyse(index).res_only:
        found.append(report(
            CODE,
            f"RES '{mark.name}' in {rung_no(mark.rung)}: no timer, counter or PWM output is named "
            f"'{mark.name}' (is the name misspelt?)",
            arg_span(mark.element, mark.field),
        ))
    return found
