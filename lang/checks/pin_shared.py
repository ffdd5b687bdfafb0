"""LD401: one pin assigned to two names."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, Related, report
from ..index import ProgramIndex
from ..model import PinAssignment, Program
from .common import pin_text

CODE = rule_code(__name__)


def _key(device, assignment):
    if device is not None:
        pin = device.pin(assignment.pin)
        if pin is not None:
            return pin.number
    return str(assignment.pin).strip().upper()


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    device = index.device
    owners: dict[object, tuple[str, PinAssignment]] = {}
    for name, assignment in program.pins.items():
        if name not in index.uses or not assignment.assigned:
            continue
        key = _key(device, assignment)
        if key not in owners:
            owners[key] = (name, assignment)
            continue
        first_name, first = owners[key]
        related = []
        if first.span is not None:
            related.append(Related(first.span, f"'{first_name}' is assigned to {pin_text(first)} here"))
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, which '{first_name}' already uses",
            assignment.span,
            *related,
        ))
    return found
