"""LD211: a master relay zone that is never closed."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import warning
from .common import rung_no

CODE = register(
    "LD211", "master relay zone not closed",
    "MASTER RLY instructions work in pairs: the first one's rung opens a zone (when its rung is "
    "false, every following rung runs unpowered), the next MASTER RLY, usually alone in its rung, "
    "closes it and powers the rungs after it again. With an odd number of them the last zone runs "
    "to the end of the program; add a MASTER RLY rung where the zone should end.",
)


def check(program, index):
    relays = index.of_kind("MASTER_RELAY")
    if len(relays) % 2 == 0:
        return []
    rung, element = relays[-1]
    return [warning(
        CODE,
        f"the MASTER RLY in {rung_no(rung)} opens a zone that no later MASTER RLY closes: every rung "
        "after it depends on its rung until the end of the program",
        element.span,
    )]
