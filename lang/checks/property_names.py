"""LD216: a property reads a name the program does not have."""

from __future__ import annotations

from difflib import get_close_matches

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program, Span
from ..properties import read_properties

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for prop in read_properties(program)[0]:
        for name in prop.names():
            if name in index.names:
                continue
            close = get_close_matches(name, index.names, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            column = _column(prop.text, name)
            span = Span.at(prop.span.line, prop.span.col + column, prop.span.col + column + len(name))
            found.append(report(CODE, f"the property reads '{name}', which the program does not use{hint}", span))
    return found


def _column(text: str, name: str) -> int:
    """Where the name is first written as a whole word in the property."""
    start = 0
    while True:
        at = text.find(name, start)
        before, after = text[at - 1:at] if at > 0 else " ", text[at + len(name):at + len(name) + 1] or " "
        if at < 0 or (not (before.isalnum() or before in "_$#") and not (after.isalnum() or after in "_$#[")):
            return max(at, 0)
        start = at + 1
