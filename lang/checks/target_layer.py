"""LD501: an instruction the selected part's family cannot compile."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from ..instructions import INSTRUCTIONS
from .common import describe, rung_no

CODE = register(
    "LD501", "instruction not available on the selected part",
    "Some instructions exist only for some targets: SLEEP only on AVR, the SPI, I2C, stepper and "
    "SFR elements only with LDmicro's C back ends, BUS and the 9/14/16-segment decoders only in "
    "simulation. With a part selected, an instruction its family (AVR or PIC16) cannot compile is "
    "an error; the program can still be simulated where the simulator supports it.",
)

_FAMILY = {"avr": "AVR", "pic16": "PIC16"}


def check(program, index):
    device = index.device
    if device is None:
        return []
    layer = device.family
    found = []
    for kind, elements in index.by_kind.items():
        if kind == "PLACEHOLDER":
            continue  # an empty rung is LD212
        spec = INSTRUCTIONS.get(kind)
        if spec is None or spec.supports(layer):
            continue
        family = _FAMILY.get(layer, layer)
        for rung, element in elements:
            found.append(error(
                CODE,
                f"{describe(element)} in {rung_no(rung)} cannot be compiled for the {device.title}: "
                f"the {family} back end does not support it",
                element.span,
            ))
    return found
