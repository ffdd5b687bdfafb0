"""LD215: a line of the PROPERTIES section that is no property."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from ..properties import read_properties

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    return [report(CODE, str(problem), problem.span) for problem in read_properties(program)[1]]
