"""LD320: a bad escape in a formatted string."""

from __future__ import annotations

from ..codes import register
from ..diagnostics import error
from .common import arg_span, rung_no, scan_format, token

CODE = register(
    "LD320", "bad escape in a formatted string",
    "In the text of a formatted string, a backslash starts an escape: \\1 to \\5 (or \\-1 to \\-5, "
    "with a sign) insert the variable with that many digits, \\r \\n \\t \\b \\f \\v \\a \\e send "
    "control characters, \\xAB sends the byte 0xAB, \\\\ a backslash. Anything else is refused. "
    "LDmicro: \"Bad escape sequence following \\; for a literal backslash, use \\\\\", \"Bad escape: "
    "correct form is \\xAB.\", \"Bad escape '\\%c'\".",
)


def check(program, index):
    found = []
    for rung, element in index.of_kind("FORMATTED_STRING"):
        text = token(element.args.get("text"))
        for sequence, reason in scan_format(text)[1]:
            found.append(error(
                CODE,
                f"formatted string in {rung_no(rung)}: bad escape '{sequence}': {reason}",
                arg_span(element, "text"),
            ))
    return found
