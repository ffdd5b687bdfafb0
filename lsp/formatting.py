"""Formatting: `ladder fmt` on the open text (lang.textform.formatter's
layout, on the program the server already read: ide.incremental.format_read), sent
as the few line edits that turn the text into the formatted one, so the
cursor and undo history stay where they are. A text with errors is never
reformatted; `.ld` files are LDmicro's own format and are left as they are."""

from __future__ import annotations

import difflib
from collections.abc import Sequence

from lsprotocol import types

from ide.incremental import format_read

from .documents import LADDER


def register(server) -> None:
    @server.on(types.TEXT_DOCUMENT_FORMATTING)
    def formatting(ls, params: types.DocumentFormattingParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None or analysis.kind != LADDER:
            return None
        formatted = format_read(analysis.text, analysis.program, analysis.problems)
        if formatted is None:
            ls.log("not formatted: the file has errors", types.MessageType.Info)
            return []
        return line_edits(analysis.text, formatted)


def line_edits(old: str, new: str) -> list[types.TextEdit]:
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
    if len(a_mid) * len(b_mid) > 4_000_000:
        opcodes = [("replace", 0, len(a_mid), 0, len(b_mid))]
    else:
        opcodes = difflib.SequenceMatcher(None, a_mid, b_mid, autojunk=False).get_opcodes()
    for tag, i1, i2, j1, j2 in opcodes:
        if tag == "equal":
            continue
        start, end, text = head + i1, head + i2, "".join(b_mid[j1:j2])
        start_position = types.Position(line=start, character=0)
        end_position = types.Position(line=end, character=0)
        if end == len(a) and a and a[-1].endswith("\n") and text.endswith("\n"):
            # keep the edit inside the buffer, ending on the last line's end: Neovim 0.11+
            # adds a line for an edit that reaches past the end
            newline = "\r\n" if a[-1].endswith("\r\n") else "\n"
            last = types.Position(line=len(a) - 1, character=len(a[-1].rstrip("\r\n").encode("utf-16-le")) // 2)
            if start == end:  # an insertion after the last line
                start_position, text = last, newline + text[:-len(newline)]
            else:
                text = text[:-len(newline)]
            end_position = last
        edits.append(types.TextEdit(range=types.Range(start=start_position, end=end_position), new_text=text))
    return edits
