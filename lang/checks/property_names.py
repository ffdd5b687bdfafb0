"""LD216: a property reads a name the program does not have."""

from __future__ import annotations

from difflib import get_close_matches

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..model import Program
from ..properties import name_span, read_properties

CODE = rule_code(__name__)


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for prop in read_properties(program)[0]:
        for name in prop.names():
            if name in index.names:
                continue
            close = get_close_matches(name, index.names, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            found.append(report(CODE, f"the property reads '{name}', which the program does not use{hint}",
                                name_span(prop, name)))
    return found
