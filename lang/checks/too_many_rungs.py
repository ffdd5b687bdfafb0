"""LD214: more rungs than LDmicro loads."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program

CODE = rule_code(__name__)

MAX_RUNGS = 9999  # LDmicro's rung array (MAX_RUNGS 9999): its loader stops there


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    if len(program.rungs) <= MAX_RUNGS:
        return []
    first = program.rungs[MAX_RUNGS]
    return [report(CODE, f"the program has {len(program.rungs)} rungs; LDmicro loads only the first {MAX_RUNGS}, "
                         f"so in LDmicro it would end before rung {MAX_RUNGS + 1}", first.span)]
