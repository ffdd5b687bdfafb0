"""LD410: a pin assigned to a name that is no I/O."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import report
from ..roles import BUS_PIN_SUFFIXES
from .common import adc_names, is_assigned, pin_text, pwm_names

CODE = rule_code(__name__)


def check(program, index):
    found = []
    analog = pwm = None
    for name, assignment in program.pins.items():
        if not is_assigned(assignment) or name[:1] in ("X", "Y", "A", "P") or name not in index.uses:
            continue
        if any(suffix in name for suffix in BUS_PIN_SUFFIXES):
            continue
        if analog is None:
            analog, pwm = adc_names(index), pwm_names(index)
        if name in analog or name in pwm:
            continue
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, but only X, Y, A and P names take pins",
            assignment.span,
        ))
    return found
