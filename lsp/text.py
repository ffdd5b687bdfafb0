"""An open document's text kept as lines, changed where the edit is.

pygls's TextDocument keeps one string and applies an incremental change by
splitting the whole text into lines and joining them again: 20 to 50 ms for
a 5 MB program, on every keystroke. `LineDocument` keeps the lines (with
their endings, as pygls's `lines` gives them), replaces only the lines an
edit touches, joins the text only when it is asked for, and counts how many
lines at the start and at the end of the text no edit has touched since the
language server last read it (`take_edited`), so the reader need not
compare the whole text with the one before to find the change.

`LineWorkspace` makes the workspace's documents LineDocuments; its text and
lines are exactly pygls's for the same changes (tests/test_lsp_text.py)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from lsprotocol import types
from pygls.workspace import TextDocument, Workspace

from lang.textform.reader import Edited


def _ends_line(text: str) -> bool:
    """Whether the text ends with a line break (one `splitlines` knows)."""
    return bool(text) and text.splitlines(True)[-1] != text.splitlines()[-1]


class LineDocument(TextDocument):
    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._lines: list[str] | None = None  # None: split from _source when asked
        # lines at the start and at the end untouched since take_edited (None: unknown)
        self._unchanged: tuple[int, int] | None = None

    @property
    def lines(self) -> Sequence[str]:
        if self._lines is None:
            self._lines = self.source.splitlines(True)
        return self._lines

    @property
    def source(self) -> str:
        if self._source is None and self._lines is not None:
            self._source = "".join(self._lines)
        return super().source

    def take_edited(self) -> Edited | None:
        """The lines untouched since the last call, for the reader, then
        starts counting again; None when that is not known (the first call, a
        change of the whole text)."""
        found = self._unchanged
        lines = self.lines
        self._unchanged = (len(lines), len(lines))  # every line at the start and at the end
        if found is None:
            return None
        start, tail = found
        return Edited(start, min(tail, len(lines) - start), lines)

    def _apply_full_change(self, change: types.TextDocumentContentChangeEvent) -> None:
        super()._apply_full_change(change)
        self._lines = None
        self._unchanged = None

    def _apply_incremental_change(self, change: types.TextDocumentContentChangePartial) -> None:
        lines = self.lines
        assert isinstance(lines, list)
        if not lines:
            lines[:] = change.text.splitlines(True)
            self._source = None
            if self._unchanged is not None:
                self._unchanged = (0, 0)
            return
        at = self._position_codec.range_from_client_units(lines, change.range)
        first, last = at.start.line, at.end.line
        if first == len(lines):  # pygls: an edit at the very end of the text
            first = last = len(lines) - 1
            start_col = end_col = len(lines[-1])
        else:
            start_col, end_col = at.start.character, at.end.character
        cut = len("".join(lines[first:last])) + end_col
        old = "".join(lines[first:last + 1])
        new = old[:start_col] + change.text + old[cut:]
        end = last + 1
        # a line the edit leaves without its break runs on into the next one, and
        # a "\r" and a "\n" the edit brings together are one break
        if first > 0 and new.startswith("\n") and lines[first - 1].endswith("\r"):
            first -= 1
            new = lines[first] + new
        while end < len(lines) and (not _ends_line(new) or (new.endswith("\r") and lines[end].startswith("\n"))):
            new += lines[end]
            end += 1
        replacement = new.splitlines(True)
        lines[first:end] = replacement
        self._source = None
        if self._unchanged is not None:
            start, tail = self._unchanged
            self._unchanged = (min(start, first), min(tail, len(lines) - first - len(replacement)))


class LineWorkspace(Workspace):
    @classmethod
    def like(cls, workspace: Workspace) -> LineWorkspace:
        return cls(workspace.root_uri, workspace._sync_kind, list(workspace.folders.values()),
                   workspace.position_encoding)

    def _create_text_document(self, doc_uri: str, source: str | None = None, version: int | None = None,
                              language_id: str | None = None) -> TextDocument:
        return LineDocument(doc_uri, source=source, version=version, language_id=language_id,
                            sync_kind=self._sync_kind, position_codec=self.position_codec)
