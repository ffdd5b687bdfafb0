"""LD707: a baud rate the part's UART cannot make from the crystal, in a
program that uses the UART."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import baud_facts, baud_refusal
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
    why = baud_refusal(device, program.settings.crystal_hz, program.settings.baud)
    return [report(CODE, why, uses[0][1].span)] if why else []
