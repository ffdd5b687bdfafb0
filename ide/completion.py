"""Completion, by where the cursor is:

* on an operand of an element: the names the program already uses that this
  operand allows (its prefixes: a coil takes Y, R or M names...);
* on a blank line of the diagram between rungs: whole rungs, one per
  instruction, drawn as the formatter draws them (a snippet whose names are
  placeholders when the editor takes snippets);
* on a wire inside a rung: an element inserted there, the rung drawn again;
* in the header line: the part names; in the I/O table: the program's X, Y,
  A and P names without a row, then the pins and ports of the selected part;
* in a .ld file: instruction lines with LDmicro's defaults, and names.

Inserting into a 2-D drawing means changing several lines: an item's main
edit replaces the cursor's line (editors want a one-line range there) and
its other edits the rung's other lines.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from functools import lru_cache

from lang.instructions import INSTRUCTIONS
from lang.labels import describe, label
from lang.loader import LD_KIND, TEXT_KIND
from lang.model import Element, Span
from lang.roles import role
from lang.textform.sections import DIAGRAM, IO

from . import edits, names
from .document import Document, newline
from .edits import RangeEdit
from .locate import rail_column, word_at

MAX_NAMES = 200  # names offered at once (clangd offers 100, VS Code shows a dozen)


class Kind(Enum):
    NAME = "name"
    PART = "part"
    PIN = "pin"  # a pin or port of the I/O table
    DRAWING = "drawing"  # a rung or an element, drawn
    INSTRUCTION = "instruction"  # a .ld instruction line


@dataclass(frozen=True)
class Item:
    label: str
    kind: Kind
    detail: str
    edit: RangeEdit  # on the cursor's line
    documentation: str | None = None  # plain text
    sort: str | None = None
    filter: str | None = None
    snippet: bool = False  # the edit's text is a snippet: $1, ${2:name}, $0
    more: tuple[RangeEdit, ...] = ()  # on other lines


@dataclass(frozen=True)
class Completions:
    items: tuple[Item, ...]
    incomplete: bool = False  # there are more: ask again as more is typed


def complete(document: Document, line: int, col: int, snippets: bool) -> Completions | None:
    """What fits at (line, col); `snippets`: the editor takes snippets."""
    text = document.line(line)
    col = min(col, len(text))
    if document.kind == LD_KIND:
        return _ld(document, line, col, text)
    locator = document.locator
    section = locator.section_at(line)
    if section == "header":
        return _parts(line, col, text)
    if section == IO:
        return _io_row(document, line, col, text)
    if section != DIAGRAM:
        return None
    hit = locator.hit(line, col, end_inclusive=True)
    if hit is not None and hit.element is not None and hit.field is not None:
        return _names(document, line, col, text, hit.element.kind, hit.field)
    if hit is not None:
        if document.has_errors:
            return Completions(())
        return Completions(tuple(_insert_here(document, line, col, hit.rung)))
    if locator.rung_at(line) is None and _blankish(text):
        return Completions(tuple(_rungs(document, line, col, text, snippets)))
    if word_at(text, col) is not None:  # a rung that does not read yet: any name
        return _names(document, line, col, text, None, None)
    return Completions(())


def _word_range(text: str, col: int) -> tuple[int, int, str]:
    word = word_at(text, col)
    if word is None or word[0] > col:
        return col, col, ""
    return word[0], word[1], text[word[0]:col]


def _names(document: Document, line: int, col: int, text: str, kind: str | None, field: str | None) -> Completions:
    """The names that fit, the first MAX_NAMES of them: a big program has
    thousands, and the editor asks again as more is typed."""
    start, end, typed = _word_range(text, col)
    found = names.candidates(document.program, document.index, kind, field, typed)
    span = Span.at(line, start, end)
    drawn = document.kind == TEXT_KIND
    items = tuple(Item(name, Kind.NAME, role(name)[0], RangeEdit(_width_kept(span, text, name) if drawn else span, name))
                  for name in found[:MAX_NAMES])
    return Completions(items, len(found) > MAX_NAMES)


def _width_kept(span: Span, text: str, name: str) -> Span:
    """The word's span, taking as many of the blanks after it as the name is
    longer (one blank stays), so that what follows on the drawing's line,
    the next names and the right rail, keeps its column."""
    longer = len(name) - (span.end_col - span.col)
    after = text[span.end_col:]
    blanks = len(after) - len(after.lstrip(" "))
    if longer <= 0 or blanks - 1 < longer:
        return span
    return Span.at(span.line, span.col, span.end_col + longer)


# --- the header and the I/O table ------------------------------------------------------------

def _parts(line: int, col: int, text: str) -> Completions | None:
    start = text.find("'")
    if not text.lstrip().startswith("for") or start < 0 or col <= start:
        return None
    end = text.find("'", start + 1)
    end = end if end >= 0 else len(text)
    if col > end:
        return None
    span = Span.at(line, start + 1, end)
    return Completions(tuple(Item(name, Kind.PART, detail, RangeEdit(span, name)) for name, detail in names.part_candidates()))


def _io_row(document: Document, line: int, col: int, text: str) -> Completions | None:
    column = text[:col].count("|")
    cells = text.split("|")
    if column == 0:
        start, end, _ = _word_range(text, col)
        span = Span.at(line, start, end)
        return Completions(tuple(Item(n, Kind.NAME, role(n)[0], RangeEdit(span, n))
                                 for n in names.unassigned_io_names(document.program, document.index)))
    if column not in (2, 3):
        return None
    name = cells[0].strip()
    bounds = [i for i, ch in enumerate(text) if ch == "|"]
    left = bounds[column - 1] + 1
    right = bounds[column] if len(bounds) > column else len(text)
    span = Span.at(line, left, right)
    typed = text[left:col]
    items = []
    for position, (number, port, pin_label) in enumerate(names.pin_candidates(document.program, name)):
        value = str(number) if column == 2 else port
        new_text = f" {value:>3} " if column == 2 else f" {value:<5} "
        items.append(Item(value, Kind.PIN, pin_label if column == 2 else f"pin {number}: {pin_label}",
                          RangeEdit(span, new_text), sort=f"{position:04d}", filter=typed + value))
    return Completions(tuple(items))


# --- whole rungs and elements -------------------------------------------------------------------

def _blankish(text: str) -> bool:
    """A diagram line with nothing drawn on it, or one word typed."""
    rail = rail_column(text)
    body = text[rail + 2:] if rail >= 0 else text
    return len(body.replace("|", " ").split()) <= 1 and "[END]" not in text


@lru_cache(maxsize=512)
def _rung_snippet(kind: str, frame: edits.Frame) -> tuple[tuple[str, ...], tuple[tuple[int, int, int], ...]]:
    lines, places = edits.drawn_operands(edits.example_rung(kind), 1, frame)
    return tuple(lines), tuple(places)


def _escape(text: str) -> str:
    return text.replace("\\", "\\\\").replace("$", "\\$").replace("}", "\\}")


def snippet_text(lines: tuple[str, ...], places: tuple[tuple[int, int, int], ...], nl: str) -> str:
    """The lines as a snippet whose places, (line, column, end column), are
    its tab stops, numbered in order."""
    out = []
    number = 1
    by_line: dict[int, list[tuple[int, int]]] = {}
    for line, col, end in places:
        by_line.setdefault(line, []).append((col, end))
    for index, line_text in enumerate(lines):
        pieces, pos = [], 0
        for col, end in sorted(by_line.get(index, [])):
            pieces.append(_escape(line_text[pos:col]))
            pieces.append(f"${{{number}:{_escape(line_text[col:end])}}}")
            number += 1
            pos = end
        pieces.append(_escape(line_text[pos:]))
        out.append("".join(pieces))
    return nl.join(out)


def _rungs(document: Document, line: int, col: int, text: str, snippets: bool) -> list[Item]:
    frame = edits.frame_of(document.text, document.program)
    nl = newline(document.text)
    number = document.locator.rungs_above(line) + 1
    span = Span.at(line, 0, len(text))
    blank = frame.blank.rstrip() if rail_column(text) >= 0 else ""
    typed = text[:col]
    items = []
    for order, kind in enumerate(_menu()):
        try:
            snippet, places = _rung_snippet(kind, frame)
        except edits.EditError:
            continue
        lines = list(snippet)
        for index, drawn in enumerate(lines):
            if drawn[:frame.margin].strip().isdigit():
                lines[index] = f"{number:0{frame.margin}d}" + drawn[frame.margin:]
        if snippets:
            body = snippet_text(tuple(lines), places, nl) + nl + _escape(blank) + nl + _escape(blank) + "$0"
        else:
            body = nl.join(lines + [blank, blank])
        spec = INSTRUCTIONS[kind]
        items.append(Item(f"rung: {_keyword(kind)}", Kind.DRAWING, spec.title, RangeEdit(span, body),
                          documentation=spec.doc + "\n\n" + "\n".join(lines), sort=f"{order:03d}",
                          filter=typed + _keyword(kind) + " " + spec.title, snippet=snippets))
    return items


def _menu() -> list[str]:
    rest = sorted(k for k in INSTRUCTIONS if edits.insertable(k) and k not in edits.COMMON
                  and k not in ("SHORT", "OPEN"))
    return [k for k in edits.COMMON if k not in ("SHORT", "OPEN")] + rest


def _keyword(kind: str) -> str:
    return label(edits.new_element(kind)) if kind in ("COIL", "CONTACTS") else kind


def _insert_here(document: Document, line: int, col: int, rung_index: int) -> list[Item]:
    """Elements inserted at a place on a wire of a drawn rung."""
    locator = document.locator
    rung = document.program.rungs[rung_index]
    if rung.is_comment:
        return []
    on_line = [(locator.glyph_span(e), e) for e in rung.elements()]
    on_line = [(g, e) for g, e in on_line if g.line == line]
    if not on_line:
        return []
    left = [(g, e) for g, e in on_line if g.end_col <= col]
    anchor: Element
    if left:
        anchor, after = max(left, key=lambda item: item[0].end_col)[1], True
    else:
        anchor, after = min(on_line, key=lambda item: item[0].col)[1], False
    extent = locator.rung_lines(rung_index)
    assert extent is not None  # the rung was found where it is drawn
    first, last = extent
    frame = edits.frame_of(document.text, document.program)
    nl = newline(document.text)
    typed = document.line(line)[:col]
    end_of = len(document.line(line))
    items = []
    for order, kind in enumerate(edits.COMMON):
        try:
            changed = edits.insert_element(rung, anchor, edits.new_element(kind), after=after)
        except edits.EditError:
            continue
        lines = edits.drawn_lines(changed, edits.drawn_number(locator, rung_index), frame)
        k = line - first
        if k >= len(lines):
            continue
        main = RangeEdit(Span.at(line, 0, end_of), lines[k])
        more = []
        if k > 0:  # the lines above, up to the end of the line before the cursor's (no shared edge)
            more.append(RangeEdit(Span(first, 0, line - 1, len(document.line(line - 1))), nl.join(lines[:k])))
        rest = lines[k + 1:]
        if line < last and rest:  # the lines below, from the start of the next line
            more.append(RangeEdit(Span(line + 1, 0, last, len(document.line(last))), nl.join(rest)))
        elif line < last or rest:
            more.append(RangeEdit(Span(line, end_of, last, len(document.line(last))), "".join(nl + x for x in rest)))
        spec = INSTRUCTIONS[kind]
        where = "after" if after else "before"
        items.append(Item(f"insert {_keyword(kind)}", Kind.DRAWING, f"{spec.title}, {where} {describe(anchor)}",
                          main, sort=f"{order:03d}", filter=typed + _keyword(kind), more=tuple(more)))
    return items


# --- .ld files ---------------------------------------------------------------------------------

def _ld(document: Document, line: int, col: int, text: str) -> Completions | None:
    indent = len(text) - len(text.lstrip())
    first_word_end = indent + len(text.lstrip().split(" ")[0]) if text.strip() else indent
    if col > first_word_end:  # an operand
        hit = document.locator.hit(line, col, end_inclusive=True)
        if hit is not None and hit.element is not None and hit.field is not None:
            return _names(document, line, col, text, hit.element.kind, hit.field)
        return _names(document, line, col, text, None, None)
    if document.locator.rung_at(line) is None and text.strip() not in ("",) and \
            not any(text.strip().startswith(k) for k in INSTRUCTIONS):
        return None  # a header or I/O LIST line
    span = Span.at(line, indent, len(text))
    return Completions(tuple(
        Item(kind, Kind.INSTRUCTION, INSTRUCTIONS[kind].title, RangeEdit(span, INSTRUCTIONS[kind].example),
             documentation=INSTRUCTIONS[kind].doc)
        for kind in sorted(k for k in INSTRUCTIONS if edits.insertable(k))))
