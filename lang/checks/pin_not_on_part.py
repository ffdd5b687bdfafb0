"""LD402: a pin the selected part does not have."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import pin_text, used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    return [
        report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)}, which the {device.title} "
            f"({device.package}) does not have",
            assignment.span,
        )
        for name, assignment, pin in used_pins(program, index)
        if pin is None
    ]
