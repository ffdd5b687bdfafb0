"""LD706: a cycle time the part's cycle timer cannot make from the crystal."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..families import compiled
from ..hardware import cycle_refusal, cycle_runs_free, cycle_setting
from ..index import ProgramIndex
from ..model import Program
from .common import pwm_outputs

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter or not compiled(device):
        return []
    crystal, cycle = program.settings.crystal_hz, program.settings.cycle_us
    free = cycle_runs_free(device, crystal, cycle, {unit for _, _, unit, _ in pwm_outputs(program, index)})
    if cycle_setting(device, crystal, cycle, free) is not None:
        return []
    # the header names the part, the crystal and the cycle together
    return [report(CODE, cycle_refusal(device, crystal, cycle, free), program.settings.mcu_span)]
