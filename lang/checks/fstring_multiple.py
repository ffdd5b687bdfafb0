"""LD321: more than one variable interpolation in a formatted string."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, scan_format, token

CODE = register(
    "LD321", "formatted string interpolates more than once",
    "A formatted string sends one variable, so its text may hold one \\1..\\5 (or \\-1..\\-5) "
    "escape only. LDmicro: \"Multiple escapes (\\0-9) present in format string, not allowed.\" "
    "Use one formatted string per value.",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("FORMATTED_STRING"):
        interpolations = scan_format(token(element.args.get("text")))[0]
        if len(interpolations) > 1:
            found.append(error(
                CODE,
                f"formatted string in {rung_no(rung)} inserts its variable {len(interpolations)} times "
                f"({', '.join(interpolations)}); only one \\1..\\5 escape is allowed",
                arg_span(element, "text"),
            ))
    return found
