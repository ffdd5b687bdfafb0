"""Formatting: `ladder fmt` on the open text (lang.textform.formatter's
layout, on the program already read: ide.incremental.format_read), as the
few line edits that turn the text into the formatted one, so the cursor and
undo history stay where they are. A text with errors is never reformatted."""

from __future__ import annotations

import difflib
from collections.abc import Sequence

from lang.diagnostics import Diagnostic
from lang.model import Program, Span

from .edits import RangeEdit
from .incremental import format_read

# past this many pairs of changed lines, the changed middle is replaced whole instead of diffed
MAX_DIFF = 4_000_000


def format_edits(text: str, program: Program, problems: list[Diagnostic]) -> list[RangeEdit] | None:
    """The edits that format a text read as `program` (None: it has errors)."""
    formatted = format_read(text, program, problems)
    return None if formatted is None else line_edits(text, formatted)


def line_edits(old: str, new: str) -> list[RangeEdit]:
    """Edits replacing whole lines, from a line diff of the two texts (the
    common head and tail are skipped first: a formatter run changes a few rungs)."""
    if old == new:
        return []
    a = old.splitlines(keepends=True)
    b = new.splitlines(keepends=True)
    head = 0
    while head < len(a) and head < len(b) and a[head] == b[head]:
        head += 1
    tail = 0
    while tail < len(a) - head and tail < len(b) - head and a[-1 - tail] == b[-1 - tail]:
        tail += 1
    a_mid, b_mid = a[head:len(a) - tail], b[head:len(b) - tail]
    edits = []
    opcodes: Sequence[tuple[str, int, int, int, int]]
    if len(a_mid) * len(b_mid) > MAX_DIFF:
        opcodes = [("replace", 0, len(a_mid), 0, len(b_mid))]
    else:
        opcodes = difflib.SequenceMatcher(None, a_mid, b_mid, autojunk=False).get_opcodes()
    for tag, i1, i2, j1, j2 in opcodes:
        if tag == "equal":
            continue
        start, end, text = head + i1, head + i2, "".join(b_mid[j1:j2])
        span = Span(start, 0, end, 0)
        if end == len(a) and a and a[-1].endswith("\n") and text.endswith("\n"):
            # keep the edit inside the buffer, ending on the last line's end: Neovim 0.11+
            # adds a line for an edit that reaches past the end
            newline = "\r\n" if a[-1].endswith("\r\n") else "\n"
            last = (len(a) - 1, len(a[-1].rstrip("\r\n")))
            if start == end:  # an insertion after the last line
                span, text = Span(*last, *last), newline + text[:-len(newline)]
            else:
                span, text = Span(start, 0, *last), text[:-len(newline)]
        edits.append(RangeEdit(span, text))
    return edits
