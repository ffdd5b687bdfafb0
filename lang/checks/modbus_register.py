"""LD111: an H name, which LDmicro makes a Modbus holding register."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import label, rung_no

CODE = register(
    "LD111", "variable named as a Modbus holding register",
    "LDmicro types every integer variable whose name starts with H as a Modbus holding register "
    "(ldmicro-formats §4.2): it goes into the I/O list and the Modbus register map. That is right "
    "for a register the Modbus master reads or writes; an ordinary variable should get another name.",
)


def check(program, index):
    found = []
    for name, uses in index.uses.items():
        if not name.startswith("H"):
            continue
        for use in uses:
            if use.access == "table":
                continue
            found.append(warning(
                CODE,
                f"'{name}' ({label(use.element)}, {rung_no(use.rung)}) starts with H, so LDmicro makes it a "
                "Modbus holding register; rename it if it is an ordinary variable",
                use.span,
            ))
            break  # once per name
    return found
