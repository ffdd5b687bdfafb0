"""LD502: READ ADC on a part without an A/D converter."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import rung_no

CODE = register(
    "LD502", "READ ADC on a part without ADC",
    "The selected part has no A/D converter, so READ ADC cannot be compiled for it. LDmicro: \"No "
    "ADC or ADC not supported for selected micro.\" Choose a part with analog inputs.",
)


def check(program, index):
    device = index.device
    if device is None or device.adc:
        return []
    return [
        error(CODE, f"READ ADC in {rung_no(rung)}: the {device.title} has no A/D converter", element.span)
        for rung, element in index.of_kind("READ_ADC")
    ]
