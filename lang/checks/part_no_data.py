"""LD408: a part LDmicro knows but textladder has no pin data for."""

from __future__ import annotations

from ..codes import rule_code
from ..devices import find_device, is_known_ldmicro_name
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    mcu = program.settings.mcu
    if not mcu or find_device(mcu) is not None or not is_known_ldmicro_name(mcu):
        return []
    return [report(
        CODE,
        f"no pin data for '{mcu}': pins and peripherals are not checked for this part",
        program.settings.mcu_span,
    )]
