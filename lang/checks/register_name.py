"""LD702: a `#` name (indirect register access) that names none of the part's
registers, which the back ends have no code for."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..hardware import register_address
from ..index import ProgramIndex
from ..model import Program
from ..targets import compiled
from .common import NAMES

CODE = rule_code(__name__)
SCOPE = NAMES

# the operand kinds that hold an integer variable, which a `#` name makes a register
_INTEGER_KINDS = frozenset({"var", "operand", "delay"})


def _holds_integer(use) -> bool:
    return any(field.name == use.field and field.kind in _INTEGER_KINDS for field in use.element.spec.fields)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    device = index.device
    if not index.pins_matter or not compiled(device):
        return []
    found = []
    for name, uses in index.uses.items():
        if name[:1] != "#" or register_address(device, name) is not None:
            continue
        if any(_holds_integer(use) for use in uses):
            # the build names the first element that uses it
            found.append(report(CODE, f"'{name}' names no register of the {device.title}; indirect register "
                                      "access is not compiled", uses[0].element.span))
    return found
