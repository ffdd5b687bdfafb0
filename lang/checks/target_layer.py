"""LD501: an instruction the selected part's family cannot compile.

A warning while editing and in `ladder check` (the program can still be
simulated), an error when the program is compiled (`ladder build`, compile on
save): the caller chooses, through `ProgramIndex.for_build`.
"""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error, warning
from ..instructions import INSTRUCTIONS
from ..targets import family_of
from .common import describe, rung_no

CODE = register(
    "LD501", "instruction not available on the selected part",
    "Some instructions exist only for some targets: SLEEP only on AVR, the SPI, I2C, stepper and "
    "SFR elements only with LDmicro's C back ends, BUS and the 9/14/16-segment decoders only in "
    "simulation. With a part selected, an instruction its family's back end (AVR or PIC16) cannot "
    "compile is a warning in `ladder check` and in the editor, where the program can still be "
    "simulated if the simulator supports it, and an error when the program is compiled "
    "(`ladder build`, compile on save).",
)


def check(program, index):
    device = index.device
    family = family_of(device) if device is not None else None
    if family is None:
        return []
    severity = error if index.for_build else warning
    found = []
    for kind, elements in index.by_kind.items():
        if kind == "PLACEHOLDER":
            continue  # an empty rung is LD212
        spec = INSTRUCTIONS.get(kind)
        if spec is None or spec.supports(family.key):
            continue
        for rung, element in elements:
            found.append(severity(
                CODE,
                f"{describe(element)} in {rung_no(rung)} cannot be compiled for the {device.title}: "
                f"the {family.title} back end does not support it",
                element.span,
            ))
    return found
