"""LD409: a part name nobody knows."""

from __future__ import annotations

from ..codes import register
from ..devices import find_device, is_known_ldmicro_name
from ..diagnostics import error

CODE = register(
    "LD409", "unknown part",
    "The part (MICRO) name is neither a part LDmicro supports nor one of textladder's short names "
    "(atmega328p, pic16f877a...). LDmicro: \"Microcontroller '...' not supported. Defaulting to no "
    "selected MCU.\" Check the spelling; `ladder parts` lists the known names.",
)


def check(program, index):
    mcu = program.settings.mcu
    if not mcu or find_device(mcu) is not None or is_known_ldmicro_name(mcu):
        return []
    return [error(CODE, f"unknown part '{mcu}'; `ladder parts` lists the parts", program.settings.mcu_span)]
