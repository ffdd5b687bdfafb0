"""LD111: an H name, which LDmicro makes a Modbus holding register."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from .common import NAMES, rung_no

CODE = rule_code(__name__)
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for name, uses in index.uses.items():
        if not name.startswith("H"):
            continue
        for use in uses:
            if use.access == "table":
                continue
            found.append(report(
                CODE,
                f"'{name}' ({label(use.element)}, {rung_no(use.rung)}) starts with H, so LDmicro makes it a "
                "Modbus holding register; rename it if it is an ordinary variable",
                use.span,
            ))
            break  # once per name
    return found
