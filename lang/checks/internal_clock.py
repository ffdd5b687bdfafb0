"""LD716: a clock the part cannot run at: one its internal oscillator
cannot make, with the configuration word selecting it (the enhanced
mid-range PICs), or one beyond its fastest crystal with the PLL (PIC18)."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..families import compiled
from ..hardware import clock_refusal
from ..index import ProgramIndex
from ..model import Program

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter or not compiled(device):
        return []
    settings = program.settings
    refusal = clock_refusal(device, settings.crystal_hz, settings.config_word or None)
    # the header names the part and the clock together
    return [] if refusal is None else [report(CODE, refusal, settings.mcu_span)]
