"""LD322: a formatted string whose variable and text disagree."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, scan_format, token

CODE = register(
    "LD322", "formatted string variable and text disagree",
    "A formatted string with a \\3-style escape in its text needs a variable to insert, and one "
    "with a variable needs such an escape. LDmicro: \"Variable is interpolated into formatted "
    "string, but none is specified.\" / \"No variable is interpolated into formatted string, but a "
    "variable name is specified. Include a string like '\\-3', or leave variable name blank.\"",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("FORMATTED_STRING"):
        var = token(element.args.get("var"))
        interpolations = scan_format(token(element.args.get("text")))[0]
        if interpolations and not var:
            found.append(error(
                CODE,
                f"formatted string in {rung_no(rung)} inserts a variable ({interpolations[0]}) but names none",
                arg_span(element, "text"),
            ))
        elif var and not interpolations:
            found.append(error(
                CODE,
                f"formatted string in {rung_no(rung)} names the variable '{var}' but its text has no "
                "\\1..\\5 escape to insert it (e.g. \\-3); add one or leave the variable blank",
                arg_span(element, "var"),
            ))
    return found
