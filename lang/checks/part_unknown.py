"""LD409: a part name nobody knows."""

from __future__ import annotations

from ..codes import rule_code
from ..devices import find_device, is_known_ldmicro_name, similar_parts
from ..diagnostics import Diagnostic, Fix, SetPart, report
from ..index import ProgramIndex
from ..model import Program

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    mcu = program.settings.mcu
    if not mcu or find_device(mcu) is not None or is_known_ldmicro_name(mcu):
        return []
    fixes = tuple(Fix(f"Change the part to '{name}'", SetPart(name)) for name in similar_parts(mcu))
    return [report(CODE, f"unknown part '{mcu}'; `ladder parts` lists the parts", program.settings.mcu_span,
                   fixes=fixes)]
