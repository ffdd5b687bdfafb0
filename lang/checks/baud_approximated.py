"""LD713: a baud rate the part's UART makes only approximately (within what
a receiver follows), in a program that uses the UART."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import baud_approximated
from ..index import ProgramIndex
from ..model import Program
from .common import first_uart_use

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    use = first_uart_use(index)
    if use is None:
        return []
    crystal, baud = program.settings.crystal_hz, program.settings.baud
    setting = baud_approximated(index.device, crystal, baud)
    if setting is None:
        return []
    return [report(CODE, f"{baud} baud runs at {setting.actual:.0f} baud from a {crystal / 1e6:g} MHz crystal "
                         f"({100 * setting.error:.1f} % off)", use.span)]
