"""LD402: a pin the selected part does not have."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import pin_text, used_pins

CODE = register(
    "LD402", "pin not on the part",
    "The I/O assignment gives a pin number the selected part's package does not have, or a port "
    "bit name (such as PD2 or RB0) it does not have. Choose a pin of this part, or check the "
    "part (MICRO) setting.",
)


def check(program, index):
    device = index.device
    return [
        error(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, which the {device.title} "
            f"({device.package}) does not have",
            assignment.span,
        )
        for name, assignment, pin in used_pins(program, index)
        if pin is None
    ]
