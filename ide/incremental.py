"""Reading a document again and again as it is edited (the language server).

`IncrementalReader(kind).read(text)` gives exactly what `lang.loader.parse`
gives for the text (tests/test_lsp_incremental.py compares them on the corpus
and on random edits), faster when the previous text was read by the same
reader:

* An edit inside the LADDER DIAGRAM re-splits and re-reads only the rungs
  around the changed lines (a window bounded by unchanged numbered rungs); the
  other rungs are kept, moved down or up when lines were added or removed.
  Whenever the window cannot be proved to split as the whole diagram would
  (an unnumbered rung at its edge, a new END, a section title), the whole
  diagram is split again.
* Rungs are also cached by their text, whatever their line: a rung that
  moved is not read again, only its positions are shifted.
* The sections after the diagram are small and are read again every time.

It mirrors `lang.textform.reader.read_text`, built from the reader's own
pieces. One difference on purpose: the DETAILS section sets element
parameters in place, so parameters the drawing does not show are reset to
their defaults before DETAILS is applied; the reader's module-level rung
cache keeps whatever an earlier text's DETAILS set (see docs/lsp.md).
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import dataclass, field, replace

from lang import codes
from lang.diagnostics import Diagnostic, error
from lang.instructions import INSTRUCTIONS
from lang.loader import LD_KIND, parse
from lang.model import Element, Parallel, Program, Rung, Series, Span
from lang.textform import details as details_section
from lang.textform import reader as _reader
from lang.textform.rungs import read_rung
from lang.textform.sections import DETAILS, DIAGRAM, IO, SETTINGS, VARS, Section, split_sections

# instruction -> (field, default) of the parameters only DETAILS can set
UNDRAWN = {key: tuple((f.name, f.default) for f in spec.fields if not f.drawn)
           for key, spec in INSTRUCTIONS.items() if any(not f.drawn for f in spec.fields)}
CACHE_SIZE = 20000


@dataclass
class _Block:
    first: int  # first source line (an empty rung: the line showing its number)
    last: int
    rung: Rung | None  # None: the rung could not be read
    problems: list[Diagnostic]
    number_at: int | None  # offset of the numbered line from `first` (None: unnumbered)
    detailed: list[Element] = field(default_factory=list)


@dataclass
class _State:
    lines: list[str]
    title_line: int  # the LADDER DIAGRAM: line
    body_last: int  # last line of the diagram section
    end_line: int | None  # the [END] line
    blocks: list[_Block]
    raw_problems: list[Diagnostic]
    sections: list[Section] = field(default_factory=list)


class IncrementalReader:
    def __init__(self, kind: str):
        self.kind = kind
        self._state: _State | None = None
        self._cache: OrderedDict = OrderedDict()
        self.last_mode = ""  # "same", "window", "full" or "ld": how the last read went (tests, benchmarks)
        self.last_window = (0, 0)  # lines re-split by the last windowed read
        # rungs of the last read that are rungs of the read before moved by lines added
        # or removed above them: id(new rung) -> (old rung, lines moved)
        self.moved: dict[int, tuple[Rung, int]] = {}

    def read(self, text: str) -> tuple[Program, list[Diagnostic]]:
        if self.kind == LD_KIND:
            self.last_mode = "ld"
            return parse(text, self.kind)
        lines = text.splitlines()
        previous = self._state
        self.moved = {}
        state = None
        sections = None
        change = None
        if previous is not None:
            change = _difference(previous.lines, lines)
            if change is None:
                self.last_mode = "same"
                state = replace(previous, lines=lines)
                sections = previous.sections
            else:
                moved = _moved_sections(previous, lines, change)
                if moved is not None:
                    state = self._update(previous, lines, change, previous.title_line,
                                         previous.body_last + change[2])
                    if state is not None:
                        sections = moved
        if sections is None:
            sections = split_sections(lines)
            diagrams = [s for s in sections if s.title == DIAGRAM]
            if state is None and len(diagrams) == 1 and change is not None:
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
        if state is None:
            return self._assemble(lines, sections, None, None)
        return self._assemble(lines, sections, state.blocks, state.raw_problems)

    # --- the whole file, as read_text does ----------------------------------------------

    def _assemble(self, lines, sections, blocks, raw_problems) -> tuple[Program, list[Diagnostic]]:
        program = Program()
        problems: list[Diagnostic] = []
        titles = {s.title for s in sections}
        for section in sections:
            if section.title == "header":
                _reader._read_header(section, program.settings, problems, has_diagram=DIAGRAM in titles)
            elif section.title == DIAGRAM:
                if blocks is None:  # several diagrams: each read in full, the last one counts
                    state = self._full(lines, section)
                    section_blocks, section_raw = state.blocks, state.raw_problems
                else:
                    section_blocks, section_raw = blocks, raw_problems
                problems.extend(section_raw)
                rungs = []
                for block in section_blocks:
                    problems.extend(block.problems)
                    if block.rung is not None:
                        rungs.append(block.rung)
                    for element in block.detailed:
                        for name, default in UNDRAWN[element.kind]:
                            element.args[name] = default
                program.rungs = rungs
            elif section.title == IO:
                _reader._read_io(section, program, problems)
            elif section.title == VARS:
                _reader._read_vars(section, program, problems)
            elif section.title == SETTINGS:
                details_section.read_settings(section, program, problems)
            elif section.title == DETAILS:
                details_section.read_details(section, program, problems)
            else:
                problems.append(error(codes.SECTION, f"unknown section {section.title!r}",
                                      Span.at(section.title_line, 0, len(section.title) + 1)))
        if DIAGRAM not in titles:
            problems.append(error(codes.UNREADABLE, "no LADDER DIAGRAM section: this is not a ladder text file",
                                  Span.at(0, 0)))
        return program, problems

    def _full(self, lines: list[str], diagram: Section) -> _State:
        raw_problems: list[Diagnostic] = []
        raw = _reader._raw_blocks(diagram, raw_problems)
        blocks = self._blocks(raw)
        body_last = diagram.lines[-1][0] if diagram.lines else diagram.title_line
        return _State(lines, diagram.title_line, body_last, _end_line(diagram.lines), blocks, raw_problems)

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
        number_at = None
        for offset, raw in enumerate(raws[:2]):
            label = labels.get(raw[0], raw[1][:raw[2]].strip())
            if label.isdigit():
                number_at = offset
                break
        overrides = tuple((raw[0] - first, labels[raw[0]]) for raw in raws if raw[0] in labels)
        key = ("\n".join(raw[1] for raw in raws), symbol, overrides)
        cached = self._cache.get(key)
        if cached is None:
            block = [_reader._line(raw, labels.get(raw[0])) for raw in raws]
            _reader._fix_right_rail(block)
            rung, found = read_rung(block, symbol)
            cached = (rung, found, first)
            self._cache[key] = cached
            if len(self._cache) > CACHE_SIZE:
                self._cache.popitem(last=False)
        else:
            self._cache.move_to_end(key)
        rung, found, at = cached
        if at != first:
            rung = shift_rung(rung, first - at) if rung is not None else None
            found = [p.shifted(first - at) for p in found]
        return _Block(first, last, rung, list(found), number_at, _detailed(rung))

    # --- an edit ------------------------------------------------------------------------

    def _update(self, state: _State, lines: list[str], change: tuple[int, int, int], title_line: int,
                body_last: int) -> _State | None:
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
        low, high = p - 1, old_end
        i0 = 0
        while i0 < len(blocks) and blocks[i0].last < low:
            i0 += 1
        i1 = i0 - 1
        while i1 + 1 < len(blocks) and blocks[i1 + 1].first <= high:
            i1 += 1
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
            if following.number_at == 0 and window and _rail_of(window[-1][1]) >= 0:
                return None  # that line would become its name line
        raw_problems: list[Diagnostic] = []
        raw = _reader._raw_blocks(Section(DIAGRAM, -1, window), raw_problems)
        if raw and not at_section_start and not _starts_apart(window):
            return None
        new_blocks = self._blocks(raw)
        kept_after = [shift_block(b, delta) for b in blocks[i1 + 1:]] if delta else blocks[i1 + 1:]
        if delta:
            for old, new in zip(blocks[i1 + 1:], kept_after):
                if old.rung is not None and old.rung.circuit.items:
                    self.moved[id(new.rung)] = (old.rung, delta)
        problems = [q for q in state.raw_problems if q.span is None or q.span.line < start]
        problems += raw_problems
        problems += [q.shifted(delta) if delta else q for q in state.raw_problems
                     if q.span is not None and q.span.line >= end]
        self.last_mode = "window"
        self.last_window = (start, new_end)
        end_line = state.end_line + delta if state.end_line is not None else None
        return _State(lines, state.title_line, body_last, end_line, blocks[:i0] + new_blocks + kept_after, problems)


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


def _moved_sections(state: _State, lines: list[str], change) -> list[Section] | None:
    """The sections of the new text without splitting it again, when the
    change is inside the diagram's body and makes or removes no title."""
    p, old_end, delta = change
    if not state.sections or p <= state.title_line or old_end > state.body_last + 1:
        return None
    if any(_title_like(lines[n]) for n in range(p, old_end + delta)):
        return None
    if any(_title_like(state.lines[n]) for n in range(p, old_end)):
        return None
    if sum(1 for s in state.sections if s.title == DIAGRAM) != 1:
        return None
    moved = []
    for section in state.sections:
        if section.title_line <= state.title_line:
            moved.append(section)  # the header and the diagram (read through its blocks)
        elif delta == 0:
            moved.append(section)
        else:
            moved.append(Section(section.title, section.title_line + delta,
                                 [(n + delta, lines[n + delta]) for n, _ in section.lines]))
    return moved


def _rail_of(text: str) -> int:
    return _reader._rail(text)


def _numbered(text: str) -> bool:
    left = _rail_of(text)
    return left >= 0 and text[:left].strip().isdigit()


def _blank(text: str) -> bool:
    left = _rail_of(text)
    return left >= 0 and _reader._blank((0, text, left))


def _starts_apart(window: list[tuple[int, str]]) -> bool:
    """Whether the first rung drawn in the window starts a rung of its own in
    the whole diagram too: after a line with no rail, at a rung number, or on
    the name line above one (otherwise it would continue the rung before)."""
    for position, (_, text) in enumerate(window):
        if _rail_of(text) < 0 or _numbered(text):
            return True
        if not _blank(text):
            # a name line above a rung number, unless that number is an empty
            # rung's (a number right above another), which closes the rung before
            return (position + 2 < len(window) and _numbered(window[position + 1][1])
                    and not _numbered(window[position + 2][1]))
    return True


def _end_line(lines: list[tuple[int, str]]) -> int | None:
    for number, text in lines:
        if "[END]" in text and _rail_of(text) >= 0:
            return number
    return None


def _detailed(rung: Rung | None) -> list[Element]:
    if rung is None:
        return []
    return [e for e in rung.elements() if e.kind in UNDRAWN]


# --- moving a rung up or down ---------------------------------------------------------

_new = object.__new__


def shift_span(span: Span | None, delta: int) -> Span | None:
    return span.shifted(delta) if span is not None else None


def _shift_node(node, delta: int, detailed: list | None = None):
    cls = node.__class__
    if cls is Element:
        moved = _new(Element)
        state = moved.__dict__
        state.update(node.__dict__)
        state["args"] = dict(node.args)
        span = node.span
        state["span"] = None if span is None else Span(span.line + delta, span.col, span.end_line + delta,
                                                       span.end_col)
        state["arg_spans"] = {k: Span(v.line + delta, v.col, v.end_line + delta, v.end_col)
                              for k, v in node.arg_spans.items()}
        if detailed is not None and node.kind in UNDRAWN:
            detailed.append(moved)
        return moved
    if cls is Series:
        return Series([_shift_node(item, delta, detailed) for item in node.items], shift_span(node.span, delta))
    return Parallel([_shift_node(branch, delta, detailed) for branch in node.branches],
                    shift_span(node.span, delta))


def shift_rung(rung: Rung, delta: int, detailed: list | None = None) -> Rung:
    return Rung(_shift_node(rung.circuit, delta, detailed), shift_span(rung.span, delta))


def shift_block(block: _Block, delta: int) -> _Block:
    detailed: list[Element] = []
    rung = shift_rung(block.rung, delta, detailed) if block.rung is not None else None
    problems = [p.shifted(delta) for p in block.problems] if block.problems else []
    return _Block(block.first + delta, block.last + delta, rung, problems, block.number_at, detailed)


def format_read(text: str, program: Program, problems: list[Diagnostic], reflow: bool = False) -> str | None:
    """`lang.textform.formatter.format_text` for a text already read (by an
    IncrementalReader): the canonical text, or None when it has errors."""
    from lang.diagnostics import ERROR
    from lang.textform.formatter import existing_width, newline_of
    from lang.textform.writer import render_program

    if any(p.severity == ERROR for p in problems):
        return None
    formatted = render_program(program, None if reflow else existing_width(text))
    newline = newline_of(text)
    return formatted if newline == "\n" else formatted.replace("\n", newline)
