"""LD211: a master relay zone that is never closed."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from .common import rung_no

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    relays = index.of_kind("MASTER_RELAY")
    if len(relays) % 2 == 0:
        return []
    rung, element = relays[-1]
    return [report(
        CODE,
        f"the MASTER RLY in {rung_no(rung)} opens a zone that no later MASTER RLY closes: every rung "
        "after it depends on its rung until the end of the program",
        element.span,
    )]
