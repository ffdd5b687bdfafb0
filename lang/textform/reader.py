"""Reading the text form (`.ladder`, and LDmicro's "Export as Text" `.txt`)
into a Program: `read_text`, or a `TextReader` that reads a text again and
again as it is edited (the language server), re-reading only the rungs an
edit touches."""

from __future__ import annotations

import re
from bisect import bisect_left, bisect_right
from collections import Counter, OrderedDict
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from decimal import Decimal, InvalidOperation
from functools import lru_cache
from itertools import chain
from operator import attrgetter

from .. import codes
from ..diagnostics import Diagnostic, error
from ..model import (
    Element,
    Node,
    Origin,
    Parallel,
    PinAssignment,
    Program,
    PropertyLine,
    Rung,
    Series,
    Settings,
    Span,
    children,
    new_span,
)
from . import details
from .alignment import shifted
from .rungs import Line, read_rung
from .sections import DETAILS, DIAGRAM, IO, PROPERTIES, SETTINGS, VARS, Section, split_sections

HEADER_RE = re.compile(
    r"\s*(?:for\s+'(?P<mcu>.*)',|no MCU assigned,)\s*"
    r"(?:(?P<mhz>[\d.]+)\s*MHz crystal,\s*)?(?P<ms>[\d.]+)\s*ms cycle time\s*\Z"
)
RAIL_RE = re.compile(r"\|[|+]")
VAR_RE = re.compile(r"\s*(\d+)\s+bytes?\s+(\S+)")

def read_text(text: str) -> tuple[Program, list[Diagnostic]]:
    """The program of a text, and the problems found reading it."""
    return TextReader().read(text)


def _read_header(section: Section, settings: Settings, problems: list[Diagnostic], has_diagram: bool) -> None:
    for number, text in section.lines:
        if not text.strip() or text.startswith("LDmicro export text") or text.startswith("Source file:"):
            continue
        match = HEADER_RE.match(text)
        if not match:
            if has_diagram:
                problems.append(error(codes.SECTION, "expected the line `for '<part>', <f> MHz crystal, "
                                      "<t> ms cycle time`", Span.at(number, 0, len(text))))
            continue
        settings.mcu = match.group("mcu")
        if settings.mcu is not None:
            start = text.index("'") + 1
            settings.mcu_span = Span.at(number, start, start + len(settings.mcu))
        try:
            if match.group("mhz"):
                settings.crystal_hz = int(Decimal(match.group("mhz")) * 1000000)
            settings.cycle_us = int(Decimal(match.group("ms")) * 1000)
        except InvalidOperation:
            problems.append(error(codes.SECTION, "bad number in the header line", Span.at(number, 0, len(text))))


# --- the diagram ---------------------------------------------------------------------

_RAIL = re.compile(r"\|[|+]")


def _rail(text: str) -> int:
    """Column of the left rail: the first `|` followed by `|` or `+` (-1: none)."""
    found = _RAIL.search(text)
    return -1 if found is None else found.start()


def _end(text: str, left: int) -> int:
    stripped = text.rstrip()
    return len(stripped) - 2 if stripped.endswith("||") and len(stripped) - 2 > left else len(stripped)


def _blank(raw: tuple[int, str, int]) -> bool:
    _, text, left = raw
    return not text[left + 2:_end(text, left)].strip()


def _line(raw: tuple[int, str, int]) -> Line:
    number, text, left = raw
    return Line(number, text, left, _end(text, left))


def number_field(labels: Sequence[str]) -> tuple[int, int] | None:
    """(offset, number) of a rung's number, from the number fields of its
    first two lines: the last that shows one (when both do, the first is an
    empty rung's, which LDmicro draws on the next rung's name line); None:
    the rung is not numbered."""
    found = None
    for offset, label in enumerate(labels[:2]):
        if label.isdigit():
            found = offset, int(label)
    return found


def rung_blocks(section: Section, problems: list[Diagnostic]) -> list[tuple[list[Line], int]]:
    """The lines of each rung and the index of its first symbol line."""
    return [([_line(raw) for raw in raws], symbol) for raws, symbol, _ in _raw_blocks(section, problems)[0]]


def _raw_blocks(section: Section, problems: list[Diagnostic]):
    """Each rung's lines as (number, text, rail column), the index of its first
    symbol line, and labels overridden (an empty rung's number); and the
    number of the line that ends the diagram, `[END]` on a rail (None: none).

    A rung starts on the name line above a line numbered in the number field,
    or on the first drawn line after a line with no rail; a rung without a
    number whose first line starts with a wire has no name line."""
    blocks: list = []
    current: list[tuple[int, str, int]] = []
    symbol: int | None = None
    labels: dict[int, str] = {}
    end: int | None = None

    def close() -> None:
        nonlocal current, symbol
        if any(not _blank(raw) for raw in current):
            blocks.append((current, symbol))
        current, symbol = [], None

    search = _RAIL.search  # _rail, inline: every line of the diagram
    raws = [(number, text, -1 if (rail := search(text)) is None else rail.start()) for number, text in section.lines]
    for position, raw in enumerate(raws):
        number, text, left = raw
        if left < 0:
            if text.strip():
                problems.append(error(codes.BROKEN_WIRE, "this diagram line has no left rail `||`",
                                      Span.at(number, 0, len(text.rstrip()))))
            close()
            continue
        if "[END]" in text:
            close()
            end = number
            break
        label = text[:left].strip()
        if label.isdigit() and position + 1 < len(raws):
            following = raws[position + 1]
            if following[2] >= 0 and following[1][:following[2]].strip().isdigit():
                # LDmicro draws an empty rung with no rows: its number lands
                # on the next rung's name line
                close()
                blocks.append(([], None))
                labels[number] = label = ""
        if label.isdigit():
            name_line = current.pop() if current and current[-1][0] == number - 1 else None
            close()
            current = [name_line] if name_line is not None else []
            symbol = len(current)
        elif label:
            problems.append(error(codes.UNKNOWN_ELEMENT, f"{label!r} in the rung-number field",
                                  Span.at(number, 0, left)))
        current.append(raw)
    close()
    return [(*_trim(block, symbol), labels) for block, symbol in blocks], end


def _trim(block: list, symbol: int | None) -> tuple[list, int]:
    if not block:
        return block, 0
    if symbol is None:
        while block and _blank(block[0]):
            block = block[1:]
        _, text, left = block[0]
        content = text[left + 2:]
        starts_drawn = content[:1] in ("-", "+") or text[left + 1:left + 2] == "+"
        symbol = 0 if starts_drawn or content.lstrip().startswith(";") else min(1, len(block) - 1)
    else:
        drop = max(0, symbol - 1)
        block, symbol = block[drop:], symbol - drop
    while len(block) > symbol + 1 and _blank(block[-1]):
        block = block[:-1]
    return block, symbol


def _block_lines(raws: list[tuple[int, str, int]]) -> list[Line]:
    """A rung's lines, each ending at the right rail: where most lines of
    the rung end in `||` (a long name may have eaten its first `|`), else
    where `_line` ends it. Each line stripped once."""
    stripped_lines = [raw[1].rstrip() for raw in raws]
    ends = [len(stripped) - 2 for stripped in stripped_lines if stripped.endswith("||")]
    rail = None if not ends else ends[0] if ends.count(ends[0]) == len(ends) else Counter(ends).most_common(1)[0][0]
    block = []
    for (number, text, left), stripped in zip(raws, stripped_lines):
        size = len(stripped)
        railed = stripped.endswith("||")
        if rail is not None and size - 2 == rail and railed:
            end = rail
        elif rail is not None and size - 1 == rail + 1 and stripped.endswith("|"):
            end = rail + 1
        else:
            end = size - 2 if railed and size - 2 > left else size
        block.append(Line(number, text, left, end))
    return block


# --- the tables after the diagram ---------------------------------------------------------

def _read_io(section: Section, program: Program, problems: list[Diagnostic]) -> None:
    for number, text in section.lines:
        row = _io_row(text)
        if row is None:
            continue
        name, pin, column, width = row
        if name is None:  # `pin` says what is wrong with it
            problems.append(error(codes.SECTION, str(pin), Span.at(number, column, column + width)))
            continue
        known = program.pins.get(name)
        if pin in (None, 0) or (known is not None and known.assigned):
            continue
        span = Span.at(number, column, column + width)
        if known is None:
            program.pins[name] = PinAssignment(name, pin, span=span)
        else:  # its Modbus address came first, in SETTINGS
            known.pin, known.span = pin, span


# an I/O row is parsed again only when its text changes (each edit reads the whole table)
@lru_cache(maxsize=16384)
def _io_row(text: str) -> tuple[str | None, int | str | None, int, int] | None:
    """(name, pin, column and width of the name) of an I/O table row, None
    for a line that assigns nothing, (None, the problem, its column and width)
    for a pin that is none."""
    cells = [cell.strip() for cell in text.split("|")]
    if len(cells) < 3 or not cells[0] or cells[0] == "Name" or set(cells[0]) <= set("-"):
        return None
    if "UART" in cells[1]:
        return None  # LDmicro lists the UART's fixed pins here, not an assignment
    name, pin_text = cells[0], cells[2]
    port_text = cells[3] if len(cells) > 3 else ""
    pin: int | str | None = None
    if pin_text.isdigit():
        pin = int(pin_text)
    elif re.fullmatch(r"[A-Za-z]{1,2}\d{1,2}", pin_text):
        pin = pin_text.upper()
    elif not pin_text or pin_text.startswith("(not assigned"):
        if re.fullmatch(r"[A-Za-z]{1,2}\d{1,2}", port_text):
            pin = port_text.upper()
    else:
        return None, f"{pin_text!r} is not a pin number or port bit (e.g. 4 or PD2)", text.find(pin_text), len(pin_text)
    return name, pin, text.find(name), len(name)


def _read_vars(section: Section, program: Program, problems: list[Diagnostic]) -> None:
    for number, text in section.lines:
        if not text.strip():
            continue
        match = VAR_RE.match(text)
        if not match:
            problems.append(error(codes.SECTION, "expected `<n> bytes <name>`", Span.at(number, 0, len(text))))
            continue
        program.var_sizes[match.group(2)] = int(match.group(1))
        note = text[match.end():].rstrip()
        if note.strip():
            program.var_notes[match.group(2)] = note


# --- reading again after an edit ----------------------------------------------------------

CACHE_SIZE = 20000


@dataclass
class _Block:
    first: int  # first source line (an empty rung: the line showing its number)
    last: int
    rung: Rung  # an UnreadRung when it could not be read whole
    problems: list[Diagnostic]
    number_at: int | None  # offset of the numbered line from `first` (None: unnumbered)
    key: tuple | None = None  # in the rung cache
    number: int | None = None  # the rung's number as drawn (None: unnumbered, an empty rung): DETAILS names it


_first_line = attrgetter("first")
_last_line = attrgetter("last")
_block_rung = attrgetter("rung")
_rung_circuit = attrgetter("circuit")
_block_problems = attrgetter("problems")
_block_number = attrgetter("number")


@dataclass
class _State:
    lines: list[str]
    title_line: int  # the LADDER DIAGRAM: line
    body_last: int  # last line of the diagram section
    end_line: int | None  # the [END] line
    blocks: list[_Block]
    raw_problems: list[Diagnostic]
    # the blocks' rungs and problems, in order, and the block of each problem: kept
    # from one version to the next, where an edit changes them (`_update`)
    rungs: list[Rung] = field(default_factory=list)
    block_problems: list[Diagnostic] = field(default_factory=list)
    problem_blocks: list[int] = field(default_factory=list)
    sections: list[Section] = field(default_factory=list)

    def gather(self) -> _State:
        """Works out `rungs`, `block_problems` and `problem_blocks` from the blocks."""
        self.rungs = list(map(_block_rung, self.blocks))
        self.block_problems = list(chain.from_iterable(map(_block_problems, self.blocks)))
        self.problem_blocks = [number for number, block in enumerate(self.blocks) if block.problems
                               for _ in block.problems]
        return self


class TextReader:
    """Reads the text form; reading the next version of a text re-reads only
    what changed, and gives exactly what a fresh reader gives
    (tests/test_lsp_incremental.py compares them on the corpus and on random
    edits):

    * An edit inside the LADDER DIAGRAM re-splits and re-reads only the rungs
      around the changed lines (a window bounded by unchanged numbered rungs);
      the other rungs are kept (the same objects), moved down or up when lines
      were added or removed (`moved`: id(new rung) -> (old rung, lines moved)).
      Whenever the window cannot be proved to split as the whole diagram would
      (an unnumbered rung at its edge, a new END, a section title), the whole
      diagram is split again.
    * Rungs are also cached by their text, whatever their line: a rung that
      moved is not read again, only its positions are shifted.
    * The sections after the diagram are small and are read again every time.
      DETAILS sets element parameters on copies of the rungs it names
      (lang/textform/details.py): a cached rung never keeps what an earlier
      version's DETAILS set. A copy is made again only for a rung whose
      drawing or details changed; otherwise the previous version's detailed
      rung is kept (moved with its rung, and in `moved` in its place)."""

    def __init__(self, cache_size: int = CACHE_SIZE):
        self.cache_size = cache_size
        self._state: _State | None = None
        self._cache: OrderedDict = OrderedDict()
        self.last_mode = ""  # "same", "after", "window" or "full": how the last read went (tests, benchmarks)
        self.last_window = (0, 0)  # lines re-split by the last windowed read
        # rungs of the last read that are rungs of the read before moved by lines added
        # or removed above them: id(new rung) -> (old rung, lines moved)
        self.moved: dict[int, tuple[Rung, int]] = {}
        # the last text read, split in lines and in sections, for the editor's helpers to share
        self.lines: list[str] = []
        self.sections: list[Section] = []
        # for DETAILS, kept from one read to the next: the elements its lines can name (a
        # circuit stays when its rung moves), and by id(circuit) (circuit, its details, the
        # detailed rung)
        self._elements = details.ElementIndex()
        self._planner = details.Planner()
        self._detailed: dict[int, tuple[Series, details.Placed, Rung]] = {}
        self.details_copied = 0  # rungs given their details afresh, over all reads (tests)
        self.details_looked_up = 0  # DETAILS lines whose elements were looked up, over all reads (tests)

    def read(self, text: str, edited: Edited | None = None) -> tuple[Program, list[Diagnostic]]:
        """The program and the problems of `text`. `edited`, when the caller
        knows it, says which lines of the text read last no edit has touched
        since: then the text is neither split nor compared whole."""
        previous = self._state
        change: tuple[int, int, int] | None = None
        if previous is not None and edited is not None and edited.fits(previous.lines):
            lines, change = edited.apply(previous.lines)
        else:
            lines = text.splitlines()
            if previous is not None:
                change = _difference(previous.lines, lines)
        self.lines = lines
        self.moved = {}
        state = None
        sections = None
        if previous is not None:
            if change is None:
                self.last_mode = "same"
                state = replace(previous, lines=lines)
                sections = previous.sections
            else:
                found = _moved_sections(previous, lines, change)
                if found is not None:
                    moved, body_last = found
                    state = self._update(previous, lines, change, previous.title_line, body_last)
                    if state is not None:
                        sections = moved
        if sections is None:
            sections = split_sections(lines)
            diagrams = [s for s in sections if s.title == DIAGRAM]
            if state is None and len(diagrams) == 1 and change is not None and previous is not None:
                diagram = diagrams[0]
                body_last = diagram.lines[-1][0] if diagram.lines else diagram.title_line
                state = self._update(previous, lines, change, diagram.title_line, body_last)
        if state is None:
            self.last_mode = "full"
            diagrams = [s for s in sections if s.title == DIAGRAM]
            if len(diagrams) == 1:
                state = self._full(lines, diagrams[0])
        if state is not None:
            state.sections = sections
        self._state = state
        self.sections = sections
        return self._assemble(lines, sections, state)

    # --- the whole file, as read_text does ----------------------------------------------

    def _assemble(self, lines, sections, diagram: _State | None) -> tuple[Program, list[Diagnostic]]:
        program = Program()
        problems: list[Diagnostic] = []
        numbers: list[int | None] = []  # the rungs' drawn numbers
        titles = {s.title for s in sections}
        for section in sections:
            if section.title == "header":
                _read_header(section, program.settings, problems, has_diagram=DIAGRAM in titles)
            elif section.title == DIAGRAM:
                # several diagrams: each read in full, the last one counts
                state = diagram if diagram is not None else self._full(lines, section)
                problems.extend(state.raw_problems)
                problems.extend(state.block_problems)
                program.rungs = list(state.rungs)  # DETAILS replaces some
                numbers = list(map(_block_number, state.blocks))
            elif section.title == IO:
                _read_io(section, program, problems)
            elif section.title == VARS:
                _read_vars(section, program, problems)
            elif section.title == SETTINGS:
                details.read_settings(section, program, problems)
            elif section.title == DETAILS:
                self._attach_details(section, program, numbers, problems)
            elif section.title == PROPERTIES:
                # read by the checks (LD215, LD216) and `ladder verify`: lang/properties.py
                program.properties = [PropertyLine(text, number) for number, text in section.lines]
            else:
                problems.append(error(codes.SECTION, f"unknown section {section.title!r}",
                                      Span.at(section.title_line, 0, len(section.title) + 1)))
        if DIAGRAM not in titles:
            problems.append(error(codes.UNREADABLE, "no LADDER DIAGRAM section: this is not a ladder text file",
                                  Span.at(0, 0)))
        return program, problems

    def _attach_details(self, section: Section, program: Program, numbers: list[int | None],
                        problems: list[Diagnostic]) -> None:
        changed = self._elements.update(program.rungs, numbers)
        plan = self._planner.plan(section, program.rungs, problems, self._elements, changed)
        self.details_looked_up += self._planner.looked_up
        detailed: dict[int, tuple[Series, details.Placed, Rung]] = {}
        where = self._elements.where
        for circuit, placed in plan.items():
            index = where[circuit]
            rung = program.rungs[index]
            step = self.moved.pop(id(rung), None)
            kept = self._detailed.get(id(rung.circuit))
            if kept is not None and kept[0] is rung.circuit and kept[1] == placed:
                result = kept[2]
                if step is not None:  # the read rung moved: its detailed copy moves with it
                    result = _moved_rung(result, step[1])
                    self.moved[id(result)] = (kept[2], step[1])
            else:
                result = details.set_details(shift_rung(rung, 0), placed)  # a copy: its own operands
                self.details_copied += 1
            detailed[id(rung.circuit)] = (rung.circuit, placed, result)
            program.rungs[index] = result
        self._detailed = detailed

    def _full(self, lines: list[str], diagram: Section) -> _State:
        raw_problems: list[Diagnostic] = []
        raw, end_line = _raw_blocks(diagram, raw_problems)
        blocks = self._blocks(raw)
        body_last = diagram.lines[-1][0] if diagram.lines else diagram.title_line
        return _State(lines, diagram.title_line, body_last, end_line, blocks, raw_problems).gather()

    # --- rungs ------------------------------------------------------------------------

    def _blocks(self, raw) -> list[_Block]:
        blocks: list[_Block] = []
        labels = raw[0][2] if raw else {}
        overridden = iter(sorted(number for number, label in labels.items() if label == ""))
        for raws, symbol, labels in raw:
            if not raws:
                at = next(overridden, None)
                line = at if at is not None else (blocks[-1].last + 1 if blocks else 0)
                blocks.append(_Block(line, line, Rung(Series([])), [], 0))
                continue
            blocks.append(self._block(raws, symbol, labels))
        return blocks

    def _block(self, raws, symbol: int, labels: dict) -> _Block:
        first, last = raws[0][0], raws[-1][0]
        numbered = number_field([labels.get(raw[0], raw[1][:raw[2]].strip()) for raw in raws[:2]])
        number_at, number = numbered if numbered is not None else (None, None)
        # labels are overridden for an empty rung's number only: most diagrams have none
        overrides = tuple((raw[0] - first, labels[raw[0]]) for raw in raws if raw[0] in labels) if labels else ()
        key = ("\n".join([raw[1] for raw in raws]), symbol, overrides)
        cached = self._cache.get(key)
        if cached is None:
            block = _block_lines(raws)
            rung, found = read_rung(block, symbol)
            cached = (rung, found, first)
            self._cache[key] = cached
            if len(self._cache) > self.cache_size:
                self._cache.popitem(last=False)
        else:
            self._cache.move_to_end(key)
        rung, found, at = cached
        if at != first:
            rung = shift_rung(rung, first - at)
            found = [shifted(p, first - at) for p in found]
        return _Block(first, last, rung, list(found), number_at, key, number)

    def _move(self, blocks: list[_Block], delta: int) -> list[_Block]:
        """The blocks `delta` lines further down: their elements and series keep
        their identity and get their new positions in place (so that a symbol
        table built on them stays true: lang/checks/incremental.py), in new
        Rungs at the new places, which `moved` records; the rung cache follows
        them. A line added above moves every rung below: one loop, locals."""
        cache, moved, recorded = self._cache, self.moved, []
        make, span_class, block_class, move = new_span, Span, _Block, move_circuit
        for block in blocks:
            rung = block.rung
            circuit = rung.circuit
            origin = circuit._origin
            if origin is None:
                move(circuit, delta)
            else:
                origin.line += delta
            span = rung.span
            new = rung.__class__(circuit, None if span is None else
                                 make(span_class, (span[0] + delta, span[1], span[2] + delta, span[3])))
            problems = [shifted(p, delta) for p in block.problems] if block.problems else block.problems
            first = block.first + delta
            recorded.append(block_class(first, block.last + delta, new, problems, block.number_at, block.key,
                                        block.number))
            if circuit.items:
                moved[id(new)] = (rung, delta)
            if block.key is not None:
                cached = cache.get(block.key)
                if cached is not None and cached[0] is rung:
                    cache[block.key] = (new, problems, first)
        return recorded

    # --- an edit ------------------------------------------------------------------------

    def _update(self, state: _State, lines: list[str], change: tuple[int, int, int], title_line: int,
                body_last: int, low: int | None = None) -> _State | None:
        """`low`: the first old line of the blocks re-read (default: the line
        above the change)."""
        p, old_end, delta = change  # changed: old lines [p, old_end), new [p, old_end + delta)
        # the diagram section must stay where it was, the change inside its body, before END
        if title_line != state.title_line or p <= state.title_line:
            return None
        stop = state.end_line if state.end_line is not None else state.body_last + 1
        if p > stop and body_last == state.body_last:
            # after the END line: what the diagram holds did not change
            self.last_mode = "after"
            return replace(state, lines=lines)
        if body_last != state.body_last + delta:
            return None
        if old_end > stop:
            return None
        blocks = state.blocks
        # blocks touching the changed lines or the lines just around them
        low, high = p - 1 if low is None else low, old_end
        i0 = bisect_left(blocks, low, key=_last_line)
        i1 = bisect_right(blocks, high, lo=i0, key=_first_line) - 1
        start = blocks[i0 - 1].last + 1 if i0 > 0 else state.title_line + 1
        end = blocks[i1 + 1].first if i1 + 1 < len(blocks) else stop  # old coordinates, exclusive
        if start > p or end < old_end:
            return None
        new_end = end + delta
        if new_end < start:
            return None
        window = [(n, lines[n]) for n in range(start, new_end)]
        if any("[END]" in text for _, text in window):
            return None
        at_section_start = start == state.title_line + 1
        if window:
            if not at_section_start and _numbered(window[0][1]):
                return None  # its name line would be the previous rung's last line
            if _numbered(window[-1][1]) and new_end <= body_last:
                return None  # the next line decides whether it is an empty rung
        following = blocks[i1 + 1] if i1 + 1 < len(blocks) else None
        if following is not None:
            if following.number_at is None:
                return None
            if following.number_at == 0 and window and _rail(window[-1][1]) >= 0:
                return None  # that line would become its name line
        raw_problems: list[Diagnostic] = []
        raw, _ = _raw_blocks(Section(DIAGRAM, -1, window), raw_problems)  # no [END] in the window
        if raw and not at_section_start and not _starts_apart(window):
            # its first rung would continue the rung before (a rung's name line added twice, the
            # second one not above its number): that rung is read with it, not the whole diagram
            return self._update(state, lines, change, title_line, body_last, blocks[i0 - 1].first)
        new_blocks = self._blocks(raw)
        kept_after = self._move(blocks[i1 + 1:], delta) if delta else blocks[i1 + 1:]
        problems = [q for q in state.raw_problems if q.span is None or q.span.line < start]
        problems += raw_problems
        problems += [q.shifted(delta) if delta else q for q in state.raw_problems
                     if q.span is not None and q.span.line >= end]
        self.last_mode = "window"
        self.last_window = (start, new_end)
        end_line = state.end_line + delta if state.end_line is not None else None
        updated = _State(lines, state.title_line, body_last, end_line, blocks[:i0] + new_blocks + kept_after, problems)
        # the rungs and problems of the blocks before the change stay, those after it
        # move with their blocks: only the changed ones are gathered again
        grown = len(new_blocks) - (i1 + 1 - i0)
        before = bisect_left(state.problem_blocks, i0)
        after = bisect_left(state.problem_blocks, i1 + 1)
        updated.rungs = state.rungs[:i0] + list(map(_block_rung, new_blocks)) + (
            list(map(_block_rung, kept_after)) if delta else state.rungs[i1 + 1:])
        updated.block_problems = state.block_problems[:before] + list(
            chain.from_iterable(map(_block_problems, new_blocks))) + (
            list(chain.from_iterable(map(_block_problems, kept_after))) if delta else state.block_problems[after:])
        updated.problem_blocks = state.problem_blocks[:before] + [
            i0 + number for number, block in enumerate(new_blocks) for _ in block.problems] + [
            number + grown for number in state.problem_blocks[after:]]
        return updated


@dataclass(frozen=True)
class Edited:
    """What an editor knows of the text since the reader last read it: its
    `start` lines and its last `tail` lines are untouched, and `lines` is the
    whole new text's lines, with their line breaks (an editor's document)."""

    start: int
    tail: int
    lines: Sequence[str]

    def fits(self, old: list[str]) -> bool:
        return self.start + self.tail <= min(len(old), len(self.lines))

    def apply(self, old: list[str]) -> tuple[list[str], tuple[int, int, int] | None]:
        """The new text's lines (without their breaks), and the change as
        `_difference` gives it (None: no line differs)."""
        old_end, new_end = len(old) - self.tail, len(self.lines) - self.tail
        window = [(line.splitlines() or [""])[0] for line in self.lines[self.start:new_end]]
        if old_end - self.start == len(window) and old[self.start:old_end] == window:
            return old, None
        return old[:self.start] + window + old[old_end:], (self.start, old_end, new_end - old_end)


def _difference(old: list[str], new: list[str]) -> tuple[int, int, int] | None:
    """(first changed line, end of the changed old lines, lines added) or None
    when the texts are the same."""
    limit = min(len(old), len(new))
    p = 0
    while p < limit and old[p] == new[p]:
        p += 1
    if p == len(old) == len(new):
        return None
    s = 0
    while s < limit - p and old[-1 - s] == new[-1 - s]:
        s += 1
    return p, len(old) - s, len(new) - len(old)


def _title_like(text: str) -> bool:
    """Could this line be a section title (the conservative test)?"""
    return bool(text) and not text[:1].isspace() and "|" not in text and text.rstrip().endswith(":")


def _moved_sections(state: _State, lines: list[str], change) -> tuple[list[Section], int] | None:
    """The sections of the new text without splitting it again, and the
    diagram's last line, when the change is inside the diagram's body or
    inside one section after the diagram (not on the line right under its
    title, which can make a translated title an I/O table's:
    sections._is_io_table) and makes or removes no title."""
    p, old_end, delta = change
    if not state.sections or p <= state.title_line:
        return None
    if any(_title_like(lines[n]) for n in range(p, old_end + delta)):
        return None
    if any(_title_like(state.lines[n]) for n in range(p, old_end)):
        return None
    if sum(1 for s in state.sections if s.title == DIAGRAM) != 1:
        return None
    if old_end <= state.body_last + 1:
        changed, body_last = None, state.body_last + delta  # in the diagram, read through its blocks
    else:
        titles = [s.title_line for s in state.sections]
        at = bisect_right(titles, p) - 1
        changed, body_last = state.sections[at], state.body_last
        following = titles[at + 1] if at + 1 < len(titles) else len(state.lines)
        if changed.title_line <= state.title_line or old_end > following or p <= changed.title_line + 1:
            return None
    moved = []
    for section in state.sections:
        if section is changed:
            end = (following if at + 1 < len(titles) else len(state.lines)) + delta
            moved.append(Section(section.title, section.title_line,
                                 [(n, lines[n]) for n in range(section.title_line + 1, end)]))
        elif section.title_line <= state.title_line or section.title_line < p or delta == 0:
            moved.append(section)  # before the change (the diagram is read through its blocks)
        else:
            moved.append(Section(section.title, section.title_line + delta,
                                 [(n + delta, lines[n + delta]) for n, _ in section.lines]))
    return moved, body_last


def _numbered(text: str) -> bool:
    left = _rail(text)
    return left >= 0 and text[:left].strip().isdigit()


def _blank_line(text: str) -> bool:
    left = _rail(text)
    return left >= 0 and _blank((0, text, left))


def _starts_apart(window: list[tuple[int, str]]) -> bool:
    """Whether the first rung drawn in the window starts a rung of its own in
    the whole diagram too: after a line with no rail, at a rung number, or on
    the name line above one (otherwise it would continue the rung before)."""
    for position, (_, text) in enumerate(window):
        if _rail(text) < 0 or _numbered(text):
            return True
        if not _blank_line(text):
            # a name line above a rung number, unless that number is an empty
            # rung's (a number right above another), which closes the rung before
            return (position + 2 < len(window) and _numbered(window[position + 1][1])
                    and not _numbered(window[position + 2][1]))
    return True


# --- moving a rung up or down ---------------------------------------------------------



def shift_span(span: Span | None, delta: int) -> Span | None:
    return span if span is None or not delta else new_span(Span, (span[0] + delta, span[1], span[2] + delta, span[3]))


def _shift_element(node: Element, delta: int) -> Element:
    if not delta:  # a copy in place (DETAILS sets values on it): spans are immutable, shared
        return Element(node.kind, dict(node.args), node.span, dict(node.arg_spans))
    return Element(node.kind, dict(node.args), shift_span(node.span, delta),
                   {k: new_span(Span, (v[0] + delta, v[1], v[2] + delta, v[3])) for k, v in node.arg_spans.items()})


def _shift_node(node: Node, delta: int) -> Node:
    if isinstance(node, Element):
        return _shift_element(node, delta)
    # a loop, not recursion (blocks may nest a thousand deep): (block, its
    # children still to move, its moved children so far), innermost last
    frames: list[tuple[Series | Parallel, Iterator[Node], list[Node]]] = [(node, iter(children(node)), [])]
    while True:
        block, rest, done = frames[-1]
        for child in rest:
            if isinstance(child, Element):
                done.append(_shift_element(child, delta))
            else:
                frames.append((child, iter(children(child)), []))
                break
        else:
            frames.pop()
            copy = (Series if block.__class__ is Series else Parallel)(done, shift_span(block.span, delta))
            if not frames:
                return copy
            frames[-1][2].append(copy)


def shift_rung(rung: Rung, delta: int) -> Rung:
    """A copy of the rung `delta` lines further down (a cached rung read again elsewhere)."""
    circuit = _shift_node(rung.circuit, delta)
    assert isinstance(circuit, Series)  # a series is moved as a series
    return type(rung)(circuit, shift_span(rung.span, delta))


def _moved_rung(rung: Rung, delta: int) -> Rung:
    """The rung `delta` lines further down, a new Rung around the same circuit moved in place."""
    move_circuit(rung.circuit, delta)
    return type(rung)(rung.circuit, shift_span(rung.span, delta))


def move_circuit(circuit: Series, delta: int) -> None:
    """Every position in a circuit `delta` lines further down, in place, by
    its origin (lang.model.Origin): the first move gives every node of the
    circuit one, later moves cost one addition. A node that another circuit's
    origin moved before keeps its place."""
    origin = circuit._origin
    if origin is None:
        origin = Origin()
        pending: list[Node] = [circuit]  # a list, not recursion: blocks may nest a thousand deep
        pop, extend, element_class, series_class = pending.pop, pending.extend, Element, Series
        while pending:
            node = pop()
            was = node._origin
            if was is not None and was.line:
                if node.__class__ is element_class:
                    node._arg_spans = node.arg_spans
                node._span = node.span
            node._origin = origin
            if node.__class__ is not element_class:
                extend(node.items if node.__class__ is series_class else node.branches)  # type: ignore[union-attr]
    origin.line += delta
