"""LD713: a baud rate the part's UART makes only approximately (within what
a receiver follows), in a program that uses the UART."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import baud_approximated, baud_facts
from ..index import ProgramIndex
from ..model import Program
from ..targets import compiled
from .common import UART_KINDS

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter or not compiled(device) or baud_facts(device) is None:
        return []
    uses = index.of_kind(*UART_KINDS)
    if not uses:
        return []
    crystal, baud = program.settings.crystal_hz, program.settings.baud
    setting = baud_approximated(device, crystal, baud)
    if setting is None:
        return []
    return [report(CODE, f"{baud} baud runs at {setting.actual:.0f} baud from a {crystal / 1e6:g} MHz crystal "
                         f"({100 * setting.error:.1f} % off)", uses[0][1].span)]
