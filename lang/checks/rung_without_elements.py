"""LD213: a rung with no element at all."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import report
from .common import rung_no

CODE = rule_code(__name__)


def check(program, index):
    return [
        report(CODE, f"{rung_no(number)} has no elements and does nothing; delete it", rung.span)
        for number, rung in enumerate(program.rungs)
        if not rung.circuit.items
    ]
