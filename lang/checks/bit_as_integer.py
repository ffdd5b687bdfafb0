"""LD110: an X, Y or M bit name used as an integer variable."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..instructions import INSTRUCTIONS
from ..labels import label
from ..model import Program
from .common import NAMES, rung_no

CODE = rule_code(__name__)
SCOPE = NAMES

_WHAT = {"X": "an input pin", "Y": "an output pin", "M": "a Modbus coil"}
# operands that take any integer name (those with a prefix rule of their own are left out)
_GENERAL = frozenset(
    (key, f.name)
    for key, spec in INSTRUCTIONS.items()
    for f in spec.fields
    if f.kind in ("var", "operand", "delay") and not f.prefixes and key != "READ_ADC"
)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, uses in index.uses.items():
        what = _WHAT.get(name[:1])
        if what is None:
            continue
        for use in uses:
            if (use.element.kind, use.field) in _GENERAL:
                found.append(report(
                    CODE,
                    f"'{name}' is used as an integer by {label(use.element)} in {rung_no(use.rung)}, "
                    f"but a name starting with {name[0]} is {what} (a bit); rename the variable",
                    use.span,
                ))
                break  # once per name, at its first integer use
    return found
