"""A vertical connector with one glyph a column off: the `+` at its top or
bottom, or one of the two `|` between them. An easy slip when drawing by
hand; read as it stands it gives three or four errors, none of which says
what to do. Found here, it is one error at the misplaced glyph that names
the column it belongs in, and the rung is read as if the glyph were there."""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from ..codes import code
from ..diagnostics import Diagnostic

if TYPE_CHECKING:  # rungs.py reads a rung with this module's help
    from .rungs import Line

MISPLACED = code("LD014")
_LINE_RE = re.compile(r"line (\d+)\Z")

# the cells of a vertical connector, from the `+` of one symbol line to the
# `+` of the next: offset below the upper symbol line, glyph
_CONNECTOR = ((0, "+"), (1, "|"), (2, "|"), (3, "+"))


@dataclass(frozen=True)
class Move:
    row: int  # index of the glyph's line in the rung's lines
    col: int  # where the glyph is
    to: int  # the column it belongs in
    glyph: str
    anchor: int  # the rung line of the `+` it lines up with
    below_anchor: bool  # whether the glyph belongs under that `+` (else above it)
    text: str  # the glyph's line with the glyph moved

    @property
    def cells(self) -> tuple[int, int]:
        """The columns the move rewrites: from the glyph to its place."""
        return min(self.col, self.to), max(self.col, self.to) + 1

    def message(self, lines: list[Line]) -> str:
        where = "under" if self.below_anchor else "above"
        return (f"move '{self.glyph}' to column {self.to + 1}, {where} the '+' of line "
                f"{lines[self.anchor].number + 1}")


def shifted(problem: Diagnostic, lines: int) -> Diagnostic:
    """A reading problem `lines` lines further down: LD014's message names
    the line of the `+` it lines up with, which moves too."""
    moved = problem.shifted(lines)
    if problem.code != MISPLACED:
        return moved
    return replace(moved, message=_LINE_RE.sub(lambda m: f"line {int(m.group(1)) + lines}", moved.message))


def misplaced(lines: list[Line], first: int) -> list[Move]:
    """The glyphs a column off from a connector whose other three cells line
    up, one move per glyph, top to bottom."""
    moves: dict[tuple[int, int], Move] = {}
    for top in range(first, len(lines) - 3, 3):
        columns: dict[int, int] = {}
        for offset, glyph in _CONNECTOR:
            for col in _columns(lines[top + offset], glyph):
                columns[col] = columns.get(col, 0) + 1
        for col, count in columns.items():
            if count != 3:
                continue
            move = _move(lines, top, col, columns)
            if move is not None:
                moves.setdefault((move.row, move.col), move)
    return sorted(moves.values(), key=lambda m: (m.row, m.col))


def _columns(line: Line, glyph: str) -> list[int]:
    found = []
    col = line.text.find(glyph, line.start, line.end)
    while col >= 0:
        found.append(col)
        col = line.text.find(glyph, col + 1, line.end)
    return found


def _move(lines: list[Line], top: int, col: int, columns: dict[int, int]) -> Move | None:
    offset, glyph = next((o, g) for o, g in _CONNECTOR if lines[top + o].char(col) != g)
    row = top + offset
    line = lines[row]
    if line.char(col) != " " and not (glyph == "+" and line.char(col) == "-"):
        return None  # the place is taken
    sides = [c for c in (col - 1, col + 1) if line.char(c) == glyph and columns.get(c, 0) == 1]
    if len(sides) != 1:
        return None
    at = sides[0]
    if glyph == "+" and (lines[row - 1].char(at) == "|" if row > 0 else False):
        return None  # a junction of its own, joined from above
    if glyph == "+" and row + 1 < len(lines) and lines[row + 1].char(at) == "|":
        return None  # joined from below
    chars = list(line.text)
    chars[col] = glyph
    chars[at] = _left_behind(line, at, at + (at - col), glyph)
    anchor = top if offset else top + 3
    return Move(row, at, col, glyph, anchor, offset != 0, "".join(chars))


def _left_behind(line: Line, at: int, beyond: int, glyph: str) -> str:
    """What the glyph's old cell becomes: a `|` leaves a blank; a `+` on a
    symbol line leaves a wire when a wire or the rail goes on beyond it."""
    if glyph == "|":
        return " "
    if line.start <= beyond < line.end:
        return " " if line.text[beyond] == " " else "-"
    return "-" if line.text[beyond:beyond + 1] in ("|", "+") else " "
