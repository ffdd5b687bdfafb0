"""LD105: a counter instruction on a name that does not start with C."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic
from ..index import ProgramIndex
from ..instructions import COUNTERS
from ..model import Program
from .common import RUNGS, misnamed

CODE = rule_code(__name__)
SCOPE = RUNGS


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return misnamed(index, CODE, COUNTERS, "C", "counter")
