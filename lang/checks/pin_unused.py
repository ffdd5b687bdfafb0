"""LD411: a pin assigned to a name the program does not use."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import BUS_PIN_SUFFIXES, is_assigned, pin_text

CODE = register(
    "LD411", "pin assigned to an unused name",
    "The I/O assignment gives a pin to a name no instruction uses; LDmicro silently drops such "
    "entries. Usually the name was renamed in the program but not in the assignment.",
)


def check(program, index):
    found = []
    for name, assignment in program.pins.items():
        if name in index.uses or not is_assigned(assignment):
            continue
        if name == "YPlcCycleDuty" and program.settings.cycle_duty:
            continue
        if any(suffix in name for suffix in BUS_PIN_SUFFIXES):
            continue
        found.append(warning(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)} but the program does not use it",
            assignment.span,
        ))
    return found
