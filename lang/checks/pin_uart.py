"""LD406: an X or Y name on the UART pins of a program that uses the UART."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import UART_KINDS, pin_text, used_pins

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if device is None or not device.uart or not index.has_kind(*UART_KINDS):
        return []
    reserved = {pin_name: role for role, pin_name in device.uart.items()}
    found = []
    for name, assignment, pin in used_pins(program, index):
        if pin is None or pin.name not in reserved or name[:1] not in ("X", "Y"):
            continue
        found.append(report(
            CODE,
            f"'{name}' is assigned to {pin_text(assignment)} ({pin.name}), the UART {reserved[pin.name].upper()} "
            "pin, but the program uses the UART",
            assignment.span,
        ))
    return found
