"""Editing a program and redrawing only what changed: rename a name, insert,
delete or move an element, put a parallel branch around elements, insert a
rung. Each edit changes a copy of the rung's model and draws the rung again
with `render_rung`, so the drawing stays aligned; the result is a list of
`LineEdit`s (whole source lines replaced) that the language server turns into
LSP text edits. Only the text form is redrawn; in a `.ld` file a rename edits
the operand where it stands.
"""

from __future__ import annotations

import copy
import re
from collections.abc import Iterator
from dataclasses import dataclass
from typing import NamedTuple

from lang.drawing import CELL
from lang.instructions import INSTRUCTIONS
from lang.model import Element, Node, Parallel, Program, Rung, Series, Span, rung_circuit
from lang.textform.details import name_columns
from lang.textform.formatter import existing_width
from lang.textform.reader import number_field
from lang.textform.sections import DETAILS, IO, PROPERTIES, VARS
from lang.textform.writer import diagram_width, margin_width, render_rung
from lang.values import is_name

from .locate import Locator


class EditError(ValueError):
    """An edit that cannot be made; the message is for the user."""


@dataclass(frozen=True)
class LineEdit:
    """Replace source lines [first, last) (0-based) with `lines`; `first ==
    last` inserts. Lines are without line endings."""

    first: int
    last: int
    lines: tuple[str, ...]


@dataclass(frozen=True)
class TextEdit:
    """Replace columns [col, end_col) of one line."""

    line: int
    col: int
    end_col: int
    text: str


@dataclass(frozen=True)
class RangeEdit:
    """Replace the text from (span.line, span.col) to (span.end_line, span.end_col)."""

    span: Span
    text: str


# what completion and the code actions offer, in menu order
COMMON = ("CONTACTS", "COIL", "TON", "TOF", "RTO", "CTU", "CTD", "RES", "OSR", "OSF", "MOVE", "ADD", "SUB",
          "EQU", "GEQ", "LES", "SHORT", "OPEN")


def new_element(kind: str, **args: object) -> Element:
    """A new element with LDmicro's defaults (as its editor inserts it)."""
    if kind not in INSTRUCTIONS or kind in ("COMMENT",):
        raise EditError(f"no instruction {kind!r}")
    line = INSTRUCTIONS[kind].example
    from lang.ldfile import read_ld

    program, problems = read_ld(f"LDmicro0.2\n\nPROGRAM\nRUNG\n  {line}\nEND\n")
    elements = [e for _, e in program.elements()]
    if problems or len(elements) != 1:
        raise EditError(f"cannot make a new {kind}")
    element = elements[0]
    element.span = None
    element.arg_spans = {}
    for name, value in args.items():
        element.args[name] = value
    return element


def insertable(kind: str) -> bool:
    spec = INSTRUCTIONS.get(kind)
    return spec is not None and kind not in ("COMMENT", "PLACEHOLDER") and "parse" in spec.support


# --- drawing a rung back into its place ---------------------------------------------------

class Frame(NamedTuple):
    """How a file draws its diagram: its width in cells (its END rung, as the
    formatter keeps it) and the width of the rung numbers' margin."""

    columns: int
    margin: int = 4

    @property
    def blank(self) -> str:
        """A diagram line with nothing drawn on it."""
        return " " * self.margin + "||" + " " * (self.columns * CELL) + "||"

    def empty(self, line: str) -> bool:
        """Whether a diagram line has nothing drawn on it but the rails."""
        return not line[self.margin + 2:].replace("|", "").strip()


def frame_of(text: str, program: Program) -> Frame:
    return Frame(existing_width(text) or diagram_width(program), margin_width(len(program.rungs)))


def drawn_lines(rung: Rung, number: int, frame: Frame) -> list[str]:
    """The rung's lines as the formatter draws them, without the blank lines
    after its last row (the source's rung ends there too)."""
    lines = render_rung(rung, number, frame.columns, frame.margin) if rung.circuit.items else []
    while len(lines) > 2 and frame.empty(lines[-1]):
        lines.pop()
    return [line.rstrip() for line in lines]


def drawn_number(locator: Locator, index: int) -> int:
    """The number rung `index` is drawn with, else its place: a rung drawn
    again keeps its number, by which DETAILS lines name it (docs/format.md).
    The reader's rule, `number_field`."""
    extent = locator.rung_lines(index)
    if extent is None:
        return index + 1
    found = number_field([line.split("|", 1)[0].strip()
                          for line in locator.lines[extent[0]:min(extent[0] + 2, extent[1] + 1)]])
    return index + 1 if found is None else found[1]


def unused_number(locator: Locator, wanted: int) -> int:
    """`wanted`, else a number no rung is drawn with: a DETAILS line that
    names the rung drawn with a number must not reach a new rung too (the
    formatter puts the numbers in order again)."""
    taken = {drawn_number(locator, index) for index in range(len(locator.program.rungs))}
    return wanted if wanted not in taken else max(taken) + 1


def redraw(locator: Locator, text: str, index: int, rung: Rung) -> LineEdit:
    """Replace rung `index`'s lines with the drawing of `rung`."""
    extent = locator.rung_lines(index)
    if extent is None:
        raise EditError(f"rung {index + 1} is not drawn in this file")
    first, last = extent
    lines = drawn_lines(rung, drawn_number(locator, index), frame_of(text, locator.program))
    return LineEdit(first, last + 1, tuple(lines))


# --- finding an element in its circuit -------------------------------------------------------

Trail = list[tuple[Series | Parallel, int]]


def _path(node: Node, target: Element, trail: Trail) -> Trail | None:
    """[(container, index), ...] from the rung's series down to the element."""
    if isinstance(node, Element):
        return trail if node is target else None
    children = node.items if isinstance(node, Series) else node.branches
    for position, child in enumerate(children):
        found = _path(child, target, trail + [(node, position)])
        if found is not None:
            return found
    return None


def _copy_with(rung: Rung, element: Element) -> tuple[Rung, Element]:
    """A deep copy of the rung and the copy of `element` in it."""
    memo: dict[int, object] = {}
    copied = copy.deepcopy(rung, memo)
    found = memo[id(element)]
    assert isinstance(found, Element)
    return copied, found


def _series_of(rung: Rung, element: Element) -> tuple[Series, int]:
    path = _path(rung.circuit, element, [])
    if path is None:
        raise EditError("that element is not in this rung")
    container, position = path[-1]
    if isinstance(container, Parallel):
        # an element alone in a branch: make the branch a series of one
        series = Series([container.branches[position]])
        container.branches[position] = series
        return series, 0
    return container, position


def _finish(rung: Rung) -> Rung:
    circuit = rung_circuit(rung.circuit)
    if not circuit.items:
        circuit = Series([Element("PLACEHOLDER", {})])
    _check_shape(circuit)
    return Rung(circuit, rung.span)


def _check_shape(node: Node) -> None:
    """LDmicro's rule: an end-of-line element (or a parallel holding one) is
    the last thing in its series."""
    if isinstance(node, Element):
        return
    if isinstance(node, Series):
        for position, item in enumerate(node.items):
            _check_shape(item)
            if position < len(node.items) - 1 and _ends_line(item):
                raise EditError("nothing can follow a coil or another end-of-line element in its branch")
        return
    for branch in node.branches:
        _check_shape(branch)


def _ends_line(node: Node) -> bool:
    if isinstance(node, Element):
        return node.spec.eol
    if isinstance(node, Series):
        return bool(node.items) and _ends_line(node.items[-1])
    return any(_ends_line(branch) for branch in node.branches)


# --- structural edits (each returns the new rung) -----------------------------------------------

def insert_element(rung: Rung, anchor: Element | None, element: Element, after: bool = True) -> Rung:
    """Insert `element` in series before or after `anchor` (None: at the end
    of the rung, before its end-of-line element if it has one)."""
    if anchor is None:
        copied = copy.deepcopy(rung)
        items = copied.circuit.items
        position = len(items)
        if not element.spec.eol and items and _ends_line(items[-1]):
            position = len(items) - 1
        items.insert(position, element)
        copied.circuit = Series([i for i in items if not (isinstance(i, Element) and i.kind == "PLACEHOLDER")])
        return _finish(copied)
    copied, target = _copy_with(rung, anchor)
    series, position = _series_of(copied, target)
    series.items.insert(position + 1 if after else position, element)
    return _finish(copied)


def delete_element(rung: Rung, element: Element) -> Rung:
    copied, target = _copy_with(rung, element)
    series, position = _series_of(copied, target)
    del series.items[position]
    return _finish(copied)


def move_element(rung: Rung, element: Element, step: int) -> Rung:
    """Swap the element with its left (-1) or right (+1) neighbour in series."""
    copied, target = _copy_with(rung, element)
    series, position = _series_of(copied, target)
    other = position + step
    if not 0 <= other < len(series.items):
        raise EditError("there is nothing to swap with on that side")
    series.items[position], series.items[other] = series.items[other], series.items[position]
    return _finish(copied)


def add_parallel(rung: Rung, elements: list[Element], branch: Element, below: bool = True) -> Rung:
    """Put a parallel branch holding `branch` around `elements`, which must
    follow each other in one series."""
    if not elements:
        raise EditError("select the elements the branch goes around")
    copied, first = _copy_with(rung, elements[0])
    series, position = _series_of(copied, first)
    memo_ids = [_find_copy(copied, e, rung) for e in elements]
    positions = sorted(series.items.index(e) for e in memo_ids if e in series.items)
    if len(positions) != len(elements) or positions != list(range(positions[0], positions[0] + len(positions))):
        raise EditError("a parallel branch goes around elements that follow each other in one branch")
    start, end = positions[0], positions[-1] + 1
    around = Series(series.items[start:end])
    new = Series([branch])
    series.items[start:end] = [Parallel([around, new] if below else [new, around])]
    return _finish(copied)


def _find_copy(copied: Rung, original: Element, rung: Rung) -> Element:
    """The element of `copied` at the same place as `original` in `rung`."""
    originals = list(rung.elements())
    copies = list(copied.elements())
    for a, b in zip(originals, copies):
        if a is original:
            return b
    raise EditError("that element is not in this rung")


def new_rung(kinds: tuple[str, ...] = ("CONTACTS", "COIL")) -> Rung:
    return Rung(rung_circuit(Series([new_element(k) for k in kinds])))


def insert_rung(locator: Locator, text: str, index: int, rung: Rung) -> LineEdit:
    """A new rung drawn above rung `index` (or before the END line when
    `index` is the number of rungs)."""
    frame = frame_of(text, locator.program)
    lines = drawn_lines(rung, unused_number(locator, index + 1), frame)
    blank = frame.blank
    if index < len(locator.program.rungs):
        extent = locator.rung_lines(index)
        if extent is None:
            raise EditError("cannot place a rung here")
        return LineEdit(extent[0], extent[0], tuple(lines + [blank.rstrip()]))
    end = locator.diagram_end()
    if end is None:
        raise EditError("the diagram has no END rung")
    # the END line has a blank line above it; the new rung goes above that
    at = end - 1 if end > 0 and frame.empty(locator.lines[end - 1]) else end
    return LineEdit(at, at, tuple([blank.rstrip()] + lines))


# --- renaming ------------------------------------------------------------------------

_NAME_CHARS = r"[\w$#@.\[\]]"


def _word_re(name: str) -> re.Pattern[str]:
    return re.compile(rf"(?<!{_NAME_CHARS}){re.escape(name)}(?!{_NAME_CHARS})")


def rename_elements(rung: Rung, old: str, new: str) -> tuple[Rung, int]:
    """A copy of the rung with every operand naming `old` renamed; the count."""
    copied = copy.deepcopy(rung)
    count = 0
    for element in copied.elements():
        for f in element.spec.fields:
            if f.kind in ("bit", "var", "operand", "delay", "label") and element.args.get(f.name) == old:
                element.args[f.name] = new
                count += 1
    return copied, count


def rename(program: Program, locator: Locator, text: str, old: str, new: str, kind: str = "ladder"
           ) -> tuple[list[LineEdit], list[TextEdit]]:
    """Rename a name everywhere: the rungs using it are drawn again (text
    form) or edited in place (.ld), and the I/O, VAR LIST and DETAILS rows
    follow, and so do the properties that name it."""
    if not is_name(new):
        raise EditError(f"{new!r} is not a valid name (letters, digits, _; not starting with a digit)")
    if old == new:
        return [], []
    line_edits: list[LineEdit] = []
    text_edits: list[TextEdit] = []
    for index, rung in enumerate(program.rungs):
        if not any(old in (e.args.get(f.name) for f in e.spec.fields) for e in rung.elements()):
            continue
        if kind == "ld":
            for element in rung.elements():
                for f in element.spec.fields:
                    span = element.arg_spans.get(f.name)
                    if element.args.get(f.name) == old and span is not None:
                        text_edits.append(TextEdit(span.line, span.col, span.end_col, new))
            continue
        renamed, count = rename_elements(rung, old, new)
        if count:
            line_edits.append(redraw(locator, text, index, renamed))
    lines = locator.lines
    if kind == "ld":
        pattern = _word_re(old)
        found = [(number, match.start(), match.end())
                 for number in _ld_io_rows(lines) for match in pattern.finditer(lines[number])]
    else:
        found = list(names_in_sections(locator, old, (IO, VARS, DETAILS, PROPERTIES)))
    for number, start, end in found:
        line = lines[number]
        replacement = new
        # keep the I/O table's column: eat or add blanks before the next `|`
        bar = line.find("|", end)
        if kind != "ld" and bar > end and not line[end:bar].strip():
            room = bar - start - 1
            replacement = new.ljust(room) if len(new) <= room else new
            end = bar - 1 if len(new) <= room else end
        text_edits.append(TextEdit(number, start, end, replacement))
    return line_edits, text_edits


def names_in_sections(locator: Locator, name: str, titles: tuple[str, ...]) -> Iterator[tuple[int, int, int]]:
    """(line, start, end) of each place a name is written in the text form's
    sections after the diagram; in DETAILS only where a line names its
    element (a variable called `rung` is not the word of `in rung 12`)."""
    pattern = _word_re(name)
    for title in titles:
        bounds = locator.section_range(title)
        if bounds is None:
            continue
        for number in range(bounds[0] + 1, bounds[1] + 1):
            line = locator.lines[number]
            columns = name_columns(line) if title == DETAILS else (0, len(line))
            if columns is not None:
                for match in pattern.finditer(line, *columns):
                    yield number, match.start(), match.end()


def _ld_io_rows(lines: list[str]) -> list[int]:
    rows, inside = [], False
    for number, line in enumerate(lines):
        stripped = line.strip()
        if stripped == "IO LIST":
            inside = True
        elif inside and stripped == "END":
            break
        elif inside:
            rows.append(number)
    return rows


def prefixed(name: str, prefixes: str) -> list[str]:
    """`Xlamp` with the first letter each allowed prefix: `Ylamp`, `Rlamp`."""
    body = name[1:] if len(name) > 1 else name
    return [p + body for p in prefixes if p != name[:1]]


# --- whole rungs offered by completion -------------------------------------------------------

def example_rung(kind: str) -> Rung:
    """A rung that shows an instruction in use: a contact, the instruction,
    and a coil when the instruction does not end the rung itself."""
    spec = INSTRUCTIONS[kind]
    kinds: tuple[str, ...]
    if kind == "CONTACTS":
        kinds = ("CONTACTS", "COIL")
    elif kind in ("SUBPROG", "ENDSUB", "LABEL"):
        kinds = (kind,)
    elif spec.eol:
        kinds = ("CONTACTS", kind)
    else:
        kinds = ("CONTACTS", kind, "COIL")
    return new_rung(kinds)


def drawn_operands(rung: Rung, number: int, frame: Frame) -> tuple[list[str], list[tuple[int, int, int]]]:
    """The rung's drawn lines and where its names and values stand in them
    ((line in the rung, column, end column), in reading order): the fields a
    snippet lets the user fill in."""
    from lang.textform.reader import read_text

    lines = drawn_lines(rung, number, frame)
    program, problems = read_text("LADDER DIAGRAM:\n" + "\n".join(lines) + "\n")
    places = []
    if not problems:
        for _, element in program.elements():
            for f in element.spec.fields:
                span = element.arg_spans.get(f.name)
                if span is not None and f.kind in ("bit", "var", "operand", "delay", "label", "text", "int"):
                    places.append((span.line - 1, span.col, span.end_col))
    return lines, sorted(places)


def comment_rung(text: str) -> Rung:
    return Rung(Series([Element("COMMENT", {"text": text, "line_ends": ()})]))
