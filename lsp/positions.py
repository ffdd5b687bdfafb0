"""Between the core's positions (0-based lines, character columns) and LSP's
(lines, columns in the negotiated encoding: UTF-16 unless the client asks
otherwise). An ASCII document needs no conversion, which is the common case."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types

from lang.model import Span

if TYPE_CHECKING:
    from pygls.workspace import PositionCodec


class Positions:
    def __init__(self, lines: list[str], codec: PositionCodec | None, ascii_text: bool):
        self.lines = lines
        self.codec = codec
        self.ascii = ascii_text or codec is None or codec.encoding == types.PositionEncodingKind.Utf32

    def _line(self, line: int) -> str:
        return self.lines[line] if 0 <= line < len(self.lines) else ""

    def to_client(self, line: int, col: int) -> types.Position:
        return types.Position(line=max(0, line), character=self.client_column(line, col))

    def client_column(self, line: int, col: int) -> int:
        """A column in characters as the client counts it on that line."""
        col = max(0, col)
        if self.ascii or self.codec is None:
            return col
        text = self._line(max(0, line))
        if text.isascii():
            return col
        return int(self.codec.client_num_units(text[:col]))

    def from_client(self, position: types.Position) -> tuple[int, int]:
        """(line, column) in characters; a position past the end of its line or
        of the document is clamped, never an error."""
        line = max(0, position.line)
        col = max(0, position.character)
        if line >= len(self.lines):
            return max(0, len(self.lines) - 1) if self.lines else 0, col
        if self.ascii or self.codec is None:
            return line, col
        text = self.lines[line]
        if text.isascii():
            return line, col
        units = 0
        for index, ch in enumerate(text):
            if units >= col:
                return line, index
            units += self.codec.impl.code_units_for_char(ch)
        return line, len(text)

    def same_for_client(self, span: Span | None) -> bool:
        """Whether the span's positions are the client's as they are: the
        lines it starts and ends on are ASCII (or no conversion applies)."""
        if self.ascii or span is None:
            return True
        return self._line(span.line).isascii() and self._line(span.end_line).isascii()

    def range(self, span: Span | None) -> types.Range:
        line, character, end_line, end_character = self.place(span)
        return types.Range(start=types.Position(line=line, character=character),
                           end=types.Position(line=end_line, character=end_character))

    def place(self, span: Span | None) -> tuple[int, int, int, int]:
        """The span's range as the client counts it (start line, character,
        end line, character), without lsprotocol's objects; no span: 0, 0, 0, 0."""
        if span is None:
            return 0, 0, 0, 0
        return (max(0, span.line), self.client_column(span.line, span.col),
                max(0, span.end_line), self.client_column(span.end_line, span.end_col))

    def line_range(self, first: int, last_exclusive: int) -> types.Range:
        """Whole lines [first, last_exclusive)."""
        return types.Range(start=types.Position(line=first, character=0),
                           end=types.Position(line=last_exclusive, character=0))
