"""LD502: READ ADC on a part without an A/D converter."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import RUNGS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if device is None or device.adc:
        return []
    return [
        report(CODE, f"READ ADC in {rung_no(rung)}: the {device.title} has no A/D converter", element.span)
        for rung, element in index.of_kind("READ_ADC")
    ]
