"""LD401: one pin assigned to two names."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import Related, error
from .common import is_assigned, pin_text

CODE = register(
    "LD401", "pin assigned twice",
    "Each pin of the microcontroller can serve one I/O name. Two names on one pin would drive or "
    "read the same wire for two purposes. Give one of them another pin (names the program no "
    "longer uses are ignored, as LDmicro drops them).",
)


def _key(device, assignment):
    if device is not None:
        pin = device.pin(assignment.pin)
        if pin is not None:
            return pin.number
    return str(assignment.pin).strip().upper()


def check(program, index):
    found = []
    device = index.device
    owners: dict[object, tuple[str, object]] = {}
    for name, assignment in program.pins.items():
        if name not in index.uses or not is_assigned(assignment):
            continue
        key = _key(device, assignment)
        if key not in owners:
            owners[key] = (name, assignment)
            continue
        first_name, first = owners[key]
        related = []
        if first.span is not None:
            related.append(Related(first.span, f"'{first_name}' is assigned to {pin_text(first)} here"))
        found.append(error(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, which '{first_name}' already uses",
            assignment.span,
            *related,
        ))
    return found
