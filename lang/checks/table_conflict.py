"""LD124: a LUT/PWL table name that an earlier instruction used as a variable."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, label, mark_related, mark_text, rung_no
from .varflags import analyse

CODE = register(
    "LD124", "table name already used otherwise",
    "The table name of a look-up table or piecewise-linear table names data in flash; LDmicro "
    "refuses a table whose name an earlier instruction used as a variable, timer or counter: "
    "\"TABLE: variable can be used only with TABLE\". Give the table a name of its own.",
)


def check(program, index):
    found = []
    for conflict in analyse(index).conflicts:
        if conflict.kind != "table":
            continue
        mark = conflict.mark
        found.append(error(
            CODE,
            f"{label(mark.element)} table '{mark.name}' in {rung_no(mark.rung)}: the name is already used by "
            f"{mark_text(conflict.earlier[0])}; a table name can be used only for tables",
            arg_span(mark.element, mark.field),
            *mark_related(conflict.earlier),
        ))
    return found
