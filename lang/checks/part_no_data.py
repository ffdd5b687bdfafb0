"""LD408: a part LDmicro knows but textladder has no pin data for."""

from __future__ import annotations

from ..codes import register
from ..devices import find_device, is_known_ldmicro_name
from ..diagnostics import warning

CODE = register(
    "LD408", "part without pin data",
    "The selected part is one LDmicro supports, but textladder has no pin data for it, so pins, "
    "peripherals and target support are not checked (and it cannot be compiled here). The program "
    "can still be simulated.",
)


def check(program, index):
    mcu = program.settings.mcu
    if not mcu or find_device(mcu) is not None or not is_known_ldmicro_name(mcu):
        return []
    return [warning(
        CODE,
        f"no pin data for '{mcu}': pins and peripherals are not checked for this part",
        program.settings.mcu_span,
    )]
