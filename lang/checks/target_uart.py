"""LD503: UART instructions on a part without a UART."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import describe
from ..model import Program
from .common import RUNGS, UART_KINDS, rung_no

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if device is None or device.uart:
        return []
    return [
        report(CODE, f"{describe(element)} in {rung_no(rung)}: the {device.title} has no UART", element.span)
        for rung, element in index.of_kind(*UART_KINDS)
    ]
