"""LD705: PERSIST variables beyond the part's data EEPROM (none at all on some
parts, as the PIC16F72), laid out as the lowering lays them out."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..families import compiled
from ..index import ProgramIndex
from ..model import Program
from ..storage import eeprom_layout, eeprom_refusal
from .common import variable_of_uses

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    persists = [element for _, element in index.of_kind("PERSIST")]
    if not persists or not index.pins_matter or not compiled(device):
        return []
    eeprom = device.memory.get("eeprom", 0)
    for element, _, end in eeprom_layout(persists, lambda name: variable_of_uses(program, index, name)):
        refused = eeprom_refusal(end, eeprom)
        if refused:
            # the build stops at the first that does not fit
            return [report(CODE, refused, element.span)]
    return []
