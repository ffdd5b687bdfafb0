"""LD124: a LUT/PWL table name that an earlier instruction used as a variable."""

from __future__ import annotations

from ..codes import rule_code
from ..diagnostics import Diagnostic, report
from ..index import ProgramIndex
from ..labels import label
from ..model import Program
from .common import NAMES, arg_span, mark_related, mark_text, rung_no
from .varflags import analyse

CODE = rule_code(__name__)
SCOPE = NAMES


def check(program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "table":
            continue
        mark = conflict.mark
        found.append(report(
            CODE,
            f"{label(mark.element)} table '{mark.name}' in {rung_no(mark.rung)}: the name is already used by "
            f"{mark_text(conflict.earlier[0])}; a table name can be used only for tables",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
