"""LD707: a baud rate the part's UART cannot make from the crystal, in a
program that uses the UART."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import baud_refusal
from ..index import ProgramIndex
from ..model import Program
from .common import first_uart_use

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    use = first_uart_use(index)
    if use is None:
        return []
    why = baud_refusal(index.device, program.settings.crystal_hz, program.settings.baud)
    return [report(CODE, why, use.span)] if why else []
