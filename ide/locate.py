"""What stands at a place in a program's source: the rung of a line, the
element and operand under a column, the glyph of an element on its symbol
line, the section of a text file a line belongs to. Positions are 0-based
lines and character columns, as in `Span`.

A `Locator` is built once per parsed text and answers in O(log rungs + rung
size), so the language server can ask on every hover and keystroke.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass
from functools import cached_property
from itertools import compress, count
from operator import is_not

from lang.model import Element, Program, Rung, Span
from lang.textform.elements import GLYPH_RE
from lang.textform.sections import DIAGRAM, split_sections

WORD_RE = re.compile(r"[\w$#@.~']+")
_SHORT_OPEN_RE = re.compile(r"\+[- ]*\+")


@dataclass(frozen=True)
class Hit:
    rung: int  # index in program.rungs
    element: Element | None
    field: str | None  # the operand under the position, if any
    part: str  # "operand", "glyph" (the instruction), "number" (rung number field), "rung"


def word_at(text: str, col: int) -> tuple[int, int, str] | None:
    """The name-like word touching column `col` (its start, end, text)."""
    for match in WORD_RE.finditer(text):
        if match.start() <= col <= match.end():
            return match.start(), match.end(), match.group()
        if match.start() > col:
            break
    return None


def contains(span: Span, line: int, col: int, end_inclusive: bool = False) -> bool:
    """Stream containment: from (line, col) of the start to the end."""
    if (line, col) < (span.line, span.col):
        return False
    end = (span.end_line, span.end_col)
    return (line, col) <= end if end_inclusive else (line, col) < end


def in_box(span: Span, line: int, col: int, end_inclusive: bool = False) -> bool:
    """Rectangle containment: a drawn element spans its name and symbol lines
    in the same columns."""
    if not span.line <= line <= span.end_line:
        return False
    return span.col <= col <= span.end_col if end_inclusive else span.col <= col < span.end_col


class Locator:
    def __init__(self, program: Program, lines: list[str], kind: str = "ladder",
                 previous: Locator | None = None, moved: dict[int, tuple[Rung, int]] | None = None,
                 titles: list[tuple[str, int]] | None = None):
        """`previous`: the locator of the text before an edit, whose rungs'
        lines are taken for the rungs kept (the same objects) and moved
        (`moved`, as the reader gives it) instead of walking them again;
        `titles`: each section's title and title line, as the reader found
        them (else the lines are split again)."""
        self.program = program
        self.lines = lines
        self.kind = kind
        self._titles = titles
        # (first line, last line, rung index) of each drawn rung, in order, and their first lines
        self._extents: list[tuple[int, int, int]] = []
        self._starts: list[int] = []
        if previous is None or not self._follow(previous, moved or {}):
            self._walk(previous, moved or {})
        # when every rung is drawn, rung i is extent i (no table of rung lines needed)
        self._lines_of = None if len(self._extents) == len(program.rungs) else \
            {index: (first, last) for first, last, index in self._extents}

    def _follow(self, previous: Locator, moved: dict[int, tuple[Rung, int]]) -> bool:
        """The extents of the version before, those of the rungs that changed
        replaced (the kept rungs are the same objects, found without a Python
        loop over all of them): when every rung was drawn and the rungs are
        as many."""
        old_rungs, rungs = previous.program.rungs, self.program.rungs
        if len(old_rungs) != len(rungs) or previous._lines_of is not None:
            return False
        extents, starts = list(previous._extents), list(previous._starts)
        for index in compress(count(), map(is_not, rungs, old_rungs)):
            origin = moved.get(id(rungs[index]))
            if origin is not None and origin[0] is old_rungs[index]:
                first, last, _ = extents[index]
                extent: tuple[int, int] | None = (first + origin[1], last + origin[1])
            else:
                extent = self._extent(rungs[index])
            if extent is None:
                return False
            extents[index] = (extent[0], extent[1], index)
            starts[index] = extent[0]
        self._extents, self._starts = extents, starts
        return True

    def _walk(self, previous: Locator | None, moved: dict[int, tuple[Rung, int]]) -> None:
        known: dict[int, tuple[int, int]] = {}
        if previous is not None:
            rungs = previous.program.rungs
            known = {id(rungs[index]): (first, last) for first, last, index in previous._extents}
        for index, rung in enumerate(self.program.rungs):
            extent = known.get(id(rung))
            origin = moved.get(id(rung)) if extent is None and moved else None
            if origin is not None:
                before = known.get(id(origin[0]))
                if before is not None:
                    extent = (before[0] + origin[1], before[1] + origin[1])
            if extent is None:
                extent = self._extent(rung)
            if extent is None:
                continue
            self._starts.append(extent[0])
            self._extents.append((extent[0], extent[1], index))

    @staticmethod
    def _extent(rung: Rung) -> tuple[int, int] | None:
        first = rung.span.line if rung.span else None
        last = rung.span.end_line if rung.span else None
        for element in rung.elements():
            if element.span is None:
                continue
            first = element.span.line if first is None else min(first, element.span.line)
            last = element.span.end_line if last is None else max(last, element.span.end_line)
        return None if first is None or last is None else (first, last)

    # --- rungs -------------------------------------------------------------------

    def rung_at(self, line: int) -> int | None:
        """The index of the rung drawn on this line (or, in a .ld file, whose
        RUNG block holds it)."""
        position = bisect.bisect_right(self._starts, line) - 1
        if position < 0:
            return None
        first, last, index = self._extents[position]
        if first <= line <= last:
            return index
        if self.kind == "ld" and line <= last + 1:
            return index  # the END line of the RUNG block
        return None

    def rung_lines(self, index: int) -> tuple[int, int] | None:
        """First and last source line of a rung (None for a rung not drawn)."""
        if self._lines_of is not None:
            return self._lines_of.get(index)
        return self._extents[index][:2] if 0 <= index < len(self._extents) else None

    def rungs_above(self, line: int) -> int:
        """How many drawn rungs start above the line."""
        return bisect.bisect_left(self._starts, line)

    def rung_extents(self) -> list[tuple[int, int, int]]:
        """(first line, last line, rung index) of every drawn rung, in order."""
        return list(self._extents)

    # --- elements ------------------------------------------------------------------

    def hit(self, line: int, col: int, end_inclusive: bool = False) -> Hit | None:
        """What the position points at: an operand, an instruction, the rung
        number, or just a rung."""
        index = self.rung_at(line)
        if index is None:
            return None
        rung = self.program.rungs[index]
        elements = list(rung.elements())
        for element in elements:
            for field, arg_span in element.arg_spans.items():
                if arg_span.line == line and (arg_span.col <= col < arg_span.end_col
                                              or (end_inclusive and col == arg_span.end_col)):
                    return Hit(index, element, field, "operand")
        for element in elements:
            span = element.span
            if span is None:
                continue
            if self.kind == "ld":
                if contains(span, line, col, end_inclusive) or (span.line == line and col >= span.col):
                    return Hit(index, element, None, "glyph")
                continue
            if in_box(span, line, col, end_inclusive):
                return Hit(index, element, None, "glyph")
            glyph = self.glyph_span(element)
            if glyph.line == line and glyph.col <= col < glyph.end_col:
                return Hit(index, element, None, "glyph")
        text = self.lines[line] if 0 <= line < len(self.lines) else ""
        if self.kind != "ld":
            rail = _rail(text)
            if rail > 0 and col < rail and text[:rail].strip():
                return Hit(index, None, None, "number")
        elif text.strip().startswith("RUNG"):
            return Hit(index, None, None, "number")
        return Hit(index, None, None, "rung")

    def glyph_span(self, element: Element) -> Span:
        """Where the element's glyph is drawn on its symbol line (in a .ld
        file: its whole line)."""
        span = element.span
        if span is None:
            return Span(0, 0, 0, 0)
        if self.kind == "ld" or span.end_line >= len(self.lines):
            return span
        text = self.lines[span.end_line]
        if element.kind in ("SHORT", "OPEN"):
            pattern = _SHORT_OPEN_RE
        elif element.kind == "PLACEHOLDER":
            return Span(span.end_line, span.col, span.end_line, span.end_col)
        else:
            pattern = GLYPH_RE
        for match in pattern.finditer(text, span.col if span.line == span.end_line else 0):
            if match.end() == span.end_col:
                return Span(span.end_line, match.start(), span.end_line, match.end())
            if match.start() >= span.end_col:
                break
        return Span(span.end_line, span.col, span.end_line, span.end_col)

    # --- sections of a text file ------------------------------------------------------

    @cached_property
    def sections(self) -> list[tuple[str, int, int]]:
        """(title, first line, last line) of every section of a text file;
        the header's title is "header"."""
        if self.kind == "ld":
            return []
        found = []
        titles = self._titles
        if titles is None:
            titles = [(section.title, section.title_line) for section in split_sections(self.lines)]
        for position, (title, title_line) in enumerate(titles):
            first = title_line if title_line >= 0 else 0
            if position + 1 < len(titles):
                last = titles[position + 1][1] - 1
            else:
                last = len(self.lines) - 1
            found.append((title, first, max(first, last)))
        return found

    def section_at(self, line: int) -> str | None:
        for title, first, last in self.sections:
            if first <= line <= last:
                return title
        return None

    def section_range(self, title: str) -> tuple[int, int] | None:
        for found, first, last in self.sections:
            if found == title:
                return first, last
        return None

    def diagram_end(self) -> int | None:
        """The line of the END rung."""
        bounds = self.section_range(DIAGRAM)
        if bounds is None:
            return None
        for number in range(bounds[0], bounds[1] + 1):
            if "[END]" in self.lines[number]:
                return number
        return None


def _rail(text: str) -> int:
    """Column of the left rail `||` or `|+` (-1: none)."""
    left = text.find("|")
    while left >= 0 and text[left + 1:left + 2] not in ("|", "+"):
        left = text.find("|", left + 1)
    return left


def rail_column(text: str) -> int:
    return _rail(text)
