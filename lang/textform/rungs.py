"""Reading one rung of the drawing: rows of three lines (name line, symbol
line, spacer), elements recognised on each symbol line, junctions joined by
vertical connectors, and the wires reduced to a series/parallel circuit."""

from __future__ import annotations

import re
from bisect import bisect_right
from dataclasses import dataclass, replace
from functools import cache, lru_cache

from .. import codes
from ..diagnostics import Diagnostic, Fix, Related, Replace, error
from ..instructions import INSTRUCTIONS
from ..model import Element, Node, Rung, Series, Span, new_span
from .alignment import MISPLACED, Move, misplaced
from .circuit import LEFT, RIGHT, BlockSpans, Edge, Nodes, NotSeriesParallel, Plan, block_spans, build, build_at, plan_of, reduce
from .elements import GLYPH_RE, complete_args, recognise
from .renamed import ElementPlan, remember, renamed


@dataclass(slots=True)
class Line:
    """A diagram line: `left` is the column of the left rail's first `|`,
    `end` where the drawing stops (the right rail or the end of the text)."""

    number: int  # 0-based line in the file
    text: str
    left: int
    end: int

    @property
    def start(self) -> int:
        return self.left + 2

    @property
    def content(self) -> str:
        return self.text[self.left + 2:self.end]

    @property
    def blank(self) -> bool:
        return self.text[self.left + 2:self.end].isspace() or self.end <= self.left + 2

    def char(self, col: int) -> str:
        return self.text[col] if self.start <= col < self.end else " "


SYMBOL_TOKEN = re.compile(
    "(?P<glyph>" + GLYPH_RE.pattern + r")|(?P<wire>-+)|(?P<plus>\+)|(?P<gap>[ ]+)|(?P<bar>\|)|(?P<other>[^\s\-+|]+)",
    re.X,
)
TOP_TOKEN = re.compile(r"~*[\[{][^\[\]{}]*[\]}]\S*|\?[^?]*\?|\S+")
COMMENT_RE = re.compile(r"\s*; ?(.*?)\s*\Z")


@dataclass(slots=True)
class UnreadRung(Rung):
    """A rung with reading errors, kept in its place so that the rungs after
    it keep their numbers. Its circuit is the rung as read with a misplaced
    connector moved (lang/textform/alignment.py) when that was its only
    fault, else the elements it could recognise, one after the other: their
    names count as used, so that the checks of the other rungs do not call a
    name the broken rung writes "never written". The checks say nothing
    inside it (lang/loader.py, `checked`): its reading errors stand for it."""


@dataclass
class Glyph:
    line: int
    start: int
    end: int
    text: str


def read_rung(lines: list[Line], symbol_index: int) -> tuple[Rung, list[Diagnostic]]:
    """Read a rung whose first symbol line is lines[symbol_index]; the line
    above it, if any, is its first name line."""
    span = Span(lines[0].number, 0, lines[-1].number, len(lines[-1].text))
    comment = _read_comment(lines)
    if comment is not None:
        text, comment_span = comment
        element = Element("COMMENT", {"text": text, "line_ends": ()}, comment_span)
        return Rung(Series([element], comment_span), span), []
    reader = _RungReader(lines, symbol_index)
    circuit = reader.read()
    if not reader.problems:
        return Rung(_root(circuit), span), []
    moves = misplaced(lines, symbol_index)
    if not moves:
        return UnreadRung(reader.salvage(), span), reader.problems
    # read as if moved: what is still wrong then is wrong in its own right
    moved = list(lines)
    for move in moves:
        first, last = move.cells
        text = moved[move.row].text
        moved[move.row] = replace(moved[move.row], text=text[:first] + move.text[first:last] + text[last:])
    again = _RungReader(moved, symbol_index)
    circuit = again.read()
    problems = [_move_error(move, lines) for move in moves] + again.problems
    if again.problems:
        return UnreadRung(again.salvage(), span), problems
    return UnreadRung(_root(circuit), span), problems


def _root(circuit: Node) -> Series:
    """The rung's series. The reduction (lang/textform/circuit.py) makes
    circuits in the model's normal form already (it flattens a series into
    a series and a parallel into a parallel, and makes no block of one
    child), so normalising them again would only copy them."""
    return circuit if isinstance(circuit, Series) else Series([circuit], circuit.span)


def _move_error(move: Move, lines: list[Line]) -> Diagnostic:
    number = lines[move.row].number
    first, last = move.cells
    fix = Fix(f"move '{move.glyph}' to column {move.to + 1}",
              Replace(Span.at(number, first, last), move.text[first:last]))
    anchor = Related(Span.at(lines[move.anchor].number, move.to), "the '+' it lines up with")
    return replace(error(MISPLACED, move.message(lines), Span.at(number, move.col), anchor), fixes=(fix,))


def _read_comment(lines: list[Line]) -> tuple[str, Span] | None:
    if not any(";" in line.text for line in lines):  # most rungs: no line to walk
        return None
    texts = [line for line in lines if not line.blank]
    if not texts or not all(line.content.lstrip().startswith(";") for line in texts):
        return None
    parts = []
    for line in texts:
        match = COMMENT_RE.match(line.content)
        assert match is not None  # it matches any line that starts with `;`
        parts.append(match.group(1))
    first, last = texts[0], texts[-1]
    return "\n".join(parts), Span(first.number, first.start, last.number, last.end)


class _RungReader:
    def __init__(self, lines: list[Line], symbol_index: int):
        self.lines = lines
        self.first = symbol_index
        # a range: `row in symbol_rows` is arithmetic, not a walk of a tall rung's rows
        self.symbol_rows = range(symbol_index, len(lines), 3)
        self.nodes = Nodes()
        self.edges: list[Edge] = []
        self.cells: list[Cell] = []  # each edge's element as drawn, for the rung's recipe
        self.problems: list[Diagnostic] = []
        self.junctions: dict[tuple[int, int], int] = {}
        self.claimed: set[tuple[int, int]] = set()
        self._folded: dict[int, list] = {}
        self._owners: dict[int, dict[tuple[int, int], list[tuple[int, int]]]] = {}

    def problem(self, code: str, message: str, line: int, start: int, end: int | None = None) -> None:
        number = self.lines[line].number
        self.problems.append(error(code, message, Span.at(number, start, end)))

    # --- the rows ---------------------------------------------------------------

    def salvage(self) -> Series:
        """Every element of the rung that can be recognised, wired or not,
        top to bottom and left to right, as one series."""
        saved = self.problems
        self.problems = []
        found: list[Node] = []
        try:
            for row in self.symbol_rows:
                for kind, start, end, text in self._tokens(row):
                    if kind == "glyph":
                        element = self._element(row, kind, start, end, text)
                        if element is not None:
                            found.append(element)
        finally:
            self.problems = saved
        return Series(found, found[0].span.union(found[-1].span) if found and found[0].span else None)

    def read(self):
        skeleton = _skeleton(self.lines, self.first) if len(self.lines) <= _MAX_SKELETON_LINES else None
        recipe = _RECIPES.get(skeleton) if skeleton is not None else None
        if recipe is not None:
            circuit = self._cooked(recipe)
            if circuit is not None:
                return circuit
        self._connect_verticals()
        self._check_stray_connectors()
        for row in self.symbol_rows:
            self._walk_row(row, self._tokens(row))
            self._top_owners(row)  # text above no element is an error even where no element is
        self._check_spacers()
        if self.problems:
            return None
        circuit = self._circuit()
        if skeleton is not None and circuit is not None and self.edges and not self.problems:
            first = self._consecutive()
            _remember(skeleton, (tuple(self.cells), plan_of(circuit, {id(e.node): i for i, e in enumerate(self.edges)}),
                                 None if first is None else block_spans(circuit, first)))
        return circuit

    def _cooked(self, recipe: Recipe) -> Node | None:
        """The circuit of a rung whose skeleton was read before, from that
        read's recipe with this rung's own elements (None: an element this
        rung draws is no instruction: read it in full, for its error)."""
        cells, plan, spans = recipe
        lines = self.lines
        elements: list[Node] = []
        for row, kind, start, end, glyph, glyph_edges, top_span in cells:
            try:
                element = self._made(lines[row].number, kind, start, end, glyph, glyph_edges,
                                     None if top_span is None else lines[row - 1], top_span)
            except ValueError:
                return None
            if element is None:
                return None
            elements.append(element)
        first = self._consecutive() if spans is not None else None
        return build(plan, elements) if first is None or spans is None else build_at(plan, elements, spans, first)

    def _consecutive(self) -> int | None:
        """The rung's first line when its lines follow one another (as a
        rung's do), so that its blocks stand where the recipe's stood,
        counted from it."""
        lines = self.lines
        first = lines[0].number
        return first if lines[-1].number - first == len(lines) - 1 else None

    def _tokens(self, row: int) -> Tokens:
        line = self.lines[row]
        return _row_tokens(line.text[line.left:line.end], line.left)

    def _connect_verticals(self) -> None:
        """Join every `+` that has a `|` below it to the `+` three lines down."""
        lines = self.lines
        for row in self.symbol_rows:
            line = lines[row]
            for start in _row_pluses(line.text[line.left:line.end], line.left):
                node = self._junction(row, start)
                if row + 2 < len(lines) and lines[row + 1].char(start) == "|" and lines[row + 2].char(start) == "|":
                    target = row + 3
                    if target < len(lines) and lines[target].char(start) == "+":
                        self.claimed.update(((row + 1, start), (row + 2, start)))
                        self.nodes.union(node, self._junction(target, start))
                    else:
                        where = min(target, len(self.lines) - 1)
                        self.problem(codes.BAD_JUNCTION,
                                     "this vertical connector meets no `+` junction on the next symbol line",
                                     where, start)
            # the left rail joins every branch drawn from it (`|+`)
            if line.text[line.left + 1:line.left + 2] == "+":
                self.nodes.union(LEFT, self._junction(row, line.left + 1))

    def _junction(self, row: int, col: int) -> int:
        key = (row, col)
        if key not in self.junctions:
            self.junctions[key] = self.nodes.new(self.lines[row].number, col)
        return self.junctions[key]

    def _is_junction(self, row: int, col: int) -> bool:
        """A `+` is a junction when a connector leaves it up or down; else it
        is part of a SHORT or OPEN glyph."""
        up = row - 1 >= 0 and self.lines[row - 1].char(col) == "|"
        down = row + 1 < len(self.lines) and self.lines[row + 1].char(col) == "|"
        return up or down

    def _check_stray_connectors(self) -> None:
        symbol = set(self.symbol_rows)
        for index, line in enumerate(self.lines):
            if index in symbol:
                continue
            col = line.text.find("|", line.start, line.end)
            while col >= 0:
                if (index, col) not in self.claimed:
                    above = index - 1 in symbol and self.lines[index - 1].char(col) == "+"
                    below = index + 1 in symbol and self.lines[index + 1].char(col) == "+"
                    if above or below or (index + 1 < len(self.lines) and self.lines[index + 1].char(col) == "|"):
                        self.problem(codes.BAD_JUNCTION,
                                     "this connector does not join two `+` junctions in the same column",
                                     index, col)
                col = line.text.find("|", col + 1, line.end)

    def _check_spacers(self) -> None:
        for index in range(self.first + 1, len(self.lines), 3):
            line = self.lines[index]
            for match in re.finditer(r"[^\s|]+", line.content):
                self.problem(codes.STRAY_TEXT, f"{match.group()!r} stands between two rows, above no element",
                             index, line.start + match.start(), line.start + match.end())

    def _walk_row(self, row: int, tokens) -> None:
        line = self.lines[row]
        tokens = self._folded[row] = self._fold_short_open(row, tokens)
        current: int | None = None
        current_is_junction = False
        if tokens and tokens[0][0] != "gap" and tokens[0][1] == line.start:
            current = LEFT
            current_is_junction = True
        for index, (kind, start, end, text) in enumerate(tokens):
            if kind == "wire":
                if current is None:
                    self.problem(codes.BROKEN_WIRE, "this wire is not connected on its left", row, start, end)
                    return
            elif kind == "plus":
                node = self._junction(row, start)
                if current is not None:
                    self.nodes.union(current, node)
                current, current_is_junction = node, True
            elif kind in ("glyph", "short", "open"):
                if current is None:
                    self.problem(codes.BROKEN_WIRE, "this element is not connected on its left", row, start, end)
                    return
                element = self._element(row, kind, start, end, text)
                if element is None:
                    return
                self.cells.append((row, kind, start, end, text, _edges(line.text, start, end),
                                   self._top_text(row, start, end)[1]))
                output = self.nodes.new(line.number, end - 1)
                span = element.span
                assert span is not None  # _element places what it reads
                self.edges.append(Edge(current, output, element, (line.number, start), span))
                current, current_is_junction = output, False
            elif kind == "gap":
                rest = index + 1 < len(tokens)
                if current is not None and not current_is_junction and rest:
                    self.problem(codes.BROKEN_WIRE,
                                 "this branch stops before reaching a junction", row, start, end)
                    return
                if current is not None and not current_is_junction and not rest:
                    if row != self.first:
                        self.problem(codes.BROKEN_WIRE,
                                     "this branch stops before reaching a junction or the right rail",
                                     row, start, end)
                        return
                    self.nodes.union(current, RIGHT)
                current = None
            elif kind == "bar":
                self.problem(codes.BAD_JUNCTION, "a connector crossing a symbol line must be a `+`", row, start)
                return
            else:
                self.problem(codes.UNKNOWN_ELEMENT, f"unrecognised text {text!r} in the drawing", row, start, end)
                return
        if current is not None and not current_is_junction:
            self.nodes.union(current, RIGHT)

    def _fold_short_open(self, row: int, tokens):
        """`+------+` and `+      +` without connectors are SHORT and OPEN."""
        line = self.lines[row]
        if not _row_pluses(line.text[line.left:line.end], line.left):
            return tokens  # most rows: nothing to fold
        folded = []
        index = 0
        while index < len(tokens):
            kind, start, end, text = tokens[index]
            if kind == "plus" and not self._is_junction(row, start):
                if index + 2 < len(tokens):
                    middle, closing = tokens[index + 1], tokens[index + 2]
                    if (middle[0] in ("wire", "gap") and closing[0] == "plus"
                            and not self._is_junction(row, closing[1])):
                        shape = "short" if middle[0] == "wire" else "open"
                        folded.append((shape, start, closing[2], text + middle[3] + closing[3]))
                        index += 3
                        continue
                self.problem(codes.BAD_JUNCTION,
                             "this `+` has no connector above or below it", row, start)
            folded.append(tokens[index])
            index += 1
        return folded

    # --- elements -------------------------------------------------------------

    def _element(self, row: int, kind: str, start: int, end: int, glyph: str) -> Element | None:
        top_text, top_span = self._top_text(row, start, end)
        if kind in ("short", "open") and top_span is not None and top_text.strip():
            self.problem(codes.STRAY_TEXT, f"{top_text.strip()!r} stands above a {kind} circuit", row - 1,
                         top_span[0], top_span[1])
            return None
        try:
            element = self._placed(row, kind, start, end, glyph, top_span)
        except ValueError as bad:  # a value of the right shape but not a valid one
            self.problem(codes.BAD_VALUE, str(bad), row, start, end)
            return None
        if element is None:
            self.problem(codes.UNKNOWN_ELEMENT, unknown_message(glyph, top_text), row, start, end)
        return element

    def _placed(self, row: int, kind: str, start: int, end: int, glyph: str,
                top_span: tuple[int, int] | None) -> Element | None:
        """The element drawn here, at its place; None when no instruction
        draws so, ValueError for a value of the right shape but not a valid one."""
        text = self.lines[row].text
        return self._made(self.lines[row].number, kind, start, end, glyph, _edges(text, start, end),
                          None if top_span is None else self.lines[row - 1], top_span)

    @staticmethod
    def _made(number: int, kind: str, start: int, end: int, glyph: str, glyph_edges: tuple[str, str],
              name_line: Line | None, top_span: tuple[int, int] | None) -> Element | None:
        """`_placed`'s element from its symbol line's number, the characters
        either side of its glyph and the name line above it (None: no text
        on top): a rung made from its recipe has the first two there."""
        new = new_span
        if name_line is None or top_span is None:
            plan = _element_plan(kind, glyph, "", glyph_edges, _NO_EDGES)
            if plan is None:
                return None
            key, args, places = plan
            span = new(Span, (number, start, number, end))
            spans = {name: new(Span, (number, start + col, number, start + col + width))
                     for name, _, col, width in places}
            return Element(key, dict(args), span, spans)
        first, last = top_span
        name_text = name_line.text
        plan = _element_plan(kind, glyph, name_text[first:last], glyph_edges, _edges(name_text, first, last))
        if plan is None:
            return None
        key, args, places = plan
        top_number = name_line.number
        span = new(Span, (top_number, first if first < start else start, number, end))
        spans = {}
        for name, on_top, col, width in places:
            if on_top:
                at = first + col
                spans[name] = new(Span, (top_number, at, top_number, at + width))
            else:
                at = start + col
                spans[name] = new(Span, (number, at, number, at + width))
        return Element(key, dict(args), span, spans)

    def _top_text(self, row: int, start: int, end: int) -> tuple[str, tuple[int, int] | None]:
        """The text on the name line above this glyph: every word of that line
        whose columns overlap this glyph more than any other glyph's."""
        owned = self._top_owners(row).get((start, end))
        if not owned:
            return "", None
        name_line = self.lines[row - 1]
        first, last = owned[0][0], owned[-1][1]
        return name_line.text[first:last], (first, last)

    def _top_owners(self, row: int) -> dict[tuple[int, int], list[tuple[int, int]]]:
        cache = self._owners
        if row in cache:
            return cache[row]
        owners: dict[tuple[int, int], list[tuple[int, int]]] = {}
        cache[row] = owners
        if row - 1 < 0 or (row - 1) in self.symbol_rows:
            return owners
        name_line = self.lines[row - 1]
        folded = self._folded.get(row)
        if folded is None:
            folded = self._fold_short_open_quiet(row)
        glyphs = [(s, e) for kind, s, e, _ in folded if kind in ("glyph", "short", "open")]
        text = name_line.text[:name_line.end]
        # a claimed cell is a `|` inside the drawing: look up this line's own,
        # not every claimed cell of the rung for every row (a tall rung has thousands)
        connectors = []
        col = text.find("|", name_line.start)
        while col >= 0:
            if (row - 1, col) in self.claimed:
                connectors.append(col)
            col = text.find("|", col + 1)
        if connectors:
            chars = list(text)
            for col in connectors:
                chars[col] = " "  # a connector, not part of a name
            text = "".join(chars)
        # the glyphs lie left to right without overlapping: the ones a word
        # overlaps follow the first that ends after the word's start
        ends = [end for _, end in glyphs]
        count = len(glyphs)
        for match in TOP_TOKEN.finditer(text, name_line.start):
            word = match.span()
            first, last = word
            best, best_overlap = None, 0
            index = bisect_right(ends, first)
            while index < count:
                glyph = glyphs[index]
                if glyph[0] >= last:
                    break
                overlap = (last if last < glyph[1] else glyph[1]) - (first if first > glyph[0] else glyph[0])
                if overlap > best_overlap:
                    best, best_overlap = glyph, overlap
                index += 1
            if best is None:
                self.problem(codes.STRAY_TEXT, f"{match.group()!r} stands above no element", row - 1, first, last)
                continue
            owned = owners.get(best)
            if owned is None:
                owners[best] = [word]
            else:
                owned.append(word)
        return owners

    def _fold_short_open_quiet(self, row: int):
        saved = self.problems
        self.problems = []
        try:
            return self._fold_short_open(row, self._tokens(row))
        finally:
            self.problems = saved

    # --- the circuit ------------------------------------------------------------------

    def _circuit(self):
        if not self.edges:
            first = self.lines[self.first]
            span = Span.at(first.number, first.start, max(first.start + 1, first.end))
            if self.nodes.find(RIGHT) == self.nodes.find(LEFT) or first.content.lstrip().startswith("-"):
                return Series([Element("PLACEHOLDER", {}, span)], span)
            self.problems.append(error(codes.BROKEN_WIRE, "this rung has no element", span))
            return None
        outgoing = {self.nodes.find(e.start) for e in self.edges}
        for edge in self.edges:
            end = self.nodes.find(edge.end)
            if end not in outgoing and end != RIGHT:
                self.nodes.union(end, RIGHT)
        try:
            return reduce(self.edges, self.nodes)
        except NotSeriesParallel as failure:
            code = codes.EMPTY_BRANCH if "bare wire" in str(failure) else codes.NOT_SERIES_PARALLEL
            self.problems.append(error(code, str(failure), failure.span))
            return None


Tokens = tuple[tuple[str, int, int, str], ...]
# an element as drawn: its symbol line's index in the rung, token kind, columns, glyph, the
# characters either side of it (`_edges`), the columns of its text on top. The characters either
# side of a glyph are its symbol line's, which the skeleton holds, or, past the right end of the
# drawing, a rail's `|`, a blank or none: no word character either way, so a rung made from the
# recipe reads its elements as with its own (an operand's place is that of a whole word).
Cell = tuple[int, str, int, int, str, tuple[str, str], "tuple[int, int] | None"]
# each element's cells, the circuit's plan and its blocks' spans (lang/textform/circuit.py)
Recipe = tuple[tuple[Cell, ...], Plan, "BlockSpans | None"]

# A rung's skeleton is all its reading depends on but the text above its
# elements: its symbol lines as drawn, and of every other line its
# connectors and where its words stand. A converted program repeats a few
# rungs with other names: a rung whose skeleton was read before without a
# problem is made from that read's recipe, its elements read from its own
# cells, rather than walked, joined and reduced again. Bounded like the
# circuit plans (lang/textform/circuit.py), the oldest out first, and
# taller rungs are not kept (one of a kind, their skeletons large).
_RECIPES: dict[tuple, Recipe] = {}
_MAX_RECIPES = 4096
_MAX_SKELETON_LINES = 3 * 64


def _remember(skeleton: tuple, recipe: Recipe) -> None:
    if len(_RECIPES) >= _MAX_RECIPES:
        _RECIPES.pop(next(iter(_RECIPES)), None)
    _RECIPES[skeleton] = recipe


def _skeleton(lines: list[Line], first: int) -> tuple:
    """The rung's skeleton (above): where each line's rail stands, its
    symbol lines as drawn and every line masked: each character the
    reader's word pattern (TOP_TOKEN) and its connector search do not tell
    apart becomes `x`, so words and connectors stand where they stood. Two
    rungs with the same skeleton have the same symbol lines and the same
    connectors, so the same connectors join their junctions (the reader
    leaves those out of the text above a glyph). One translation a rung."""
    return (first, tuple([line.left for line in lines]),
            "\n".join([line.text[line.left:line.end] for line in lines]).translate(_MASK),
            "\n".join([line.text[line.left:line.end] for line in lines[first::3]]))


# what TOP_TOKEN and the search for `|` tell apart: whitespace, `~[]{}?|`; the rest is `x`
_MASK = {code: "x" for code in range(128) if not chr(code).isspace() and chr(code) not in "~[]{}?|"}


@lru_cache(maxsize=16384)
def _row_tokens(drawn: str, left: int) -> Tokens:
    """The tokens of a symbol line between its rails: `drawn` is the line
    from its left rail (at column `left`) to where the drawing stops.
    Cached by what is drawn, the rung number before the rail left out: a
    program repeats its symbol lines (the names stand on the line above),
    and this is the reader's hottest loop."""
    # every alternative is a named group: lastgroup is never None
    return tuple([(match.lastgroup, match.start() + left, match.end() + left, match.group())  # type: ignore[misc]
                  for match in SYMBOL_TOKEN.finditer(drawn, 2)])


@lru_cache(maxsize=65536)
def _element_plan(kind: str, glyph: str, top_text: str, glyph_edges: tuple[str, str],
                  top_edges: tuple[str, str]) -> ElementPlan | None:
    """What an element drawn so reads to: its instruction, all its operands
    and where each drawn operand stands, (name, in the text on top, column
    from the start of that text or of the glyph, width); None when no
    instruction draws so; ValueError for a value of the right shape but not
    a valid one. An operand stands where it is a whole word, so the
    characters either side of the glyph and of the text on top take part.
    Cached: a program repeats its elements, under other names too (an
    element that renames one read before: lang/textform/renamed.py)."""
    if kind in ("short", "open"):
        key, drawn = kind.upper(), {}
    else:
        copy = renamed(glyph, top_text, glyph_edges, top_edges)
        if copy is not None:
            return copy
        found = recognise(glyph, top_text)
        if found is None:
            return None
        key, values = found
        drawn = dict(values)
    places = [(False, glyph_edges[0] + glyph + glyph_edges[1], len(glyph_edges[0]), len(glyph))]
    if top_text:
        places.insert(0, (True, top_edges[0] + top_text + top_edges[1], len(top_edges[0]), len(top_text)))
    spans = []
    for name in _placed_fields(key):
        value = drawn.get(name)
        if not isinstance(value, str) or not value:
            continue
        for on_top, text, lo, width in places:
            found_at = _find_word(text, value, lo, lo + width)
            if found_at >= 0:
                spans.append((name, on_top, found_at - lo, len(value)))
                break
    plan = key, complete_args(key, drawn), tuple(spans)
    if kind == "glyph":
        remember(glyph, top_text, glyph_edges, top_edges, plan,
                 tuple((name, value) for name in _placed_fields(key) if isinstance(value := drawn.get(name), str) and value))
    return plan


def _edges(text: str, start: int, end: int) -> tuple[str, str]:
    """The characters either side of text[start:end] (none past either end)."""
    return text[start - 1:start] if start else "", text[end:end + 1]


_NO_EDGES = ("", "")


@lru_cache(maxsize=16384)
def _row_pluses(drawn: str, left: int) -> tuple[int, ...]:
    """The columns of a symbol line's `+` tokens (junctions, or the ends of a
    SHORT or OPEN)."""
    return tuple(token[1] for token in _row_tokens(drawn, left) if token[0] == "plus")


@cache
def _placed_fields(key: str) -> tuple[str, ...]:
    """The fields of an instruction whose drawn text gets a place (a name,
    a value), not a flag, an edge or a coil's kind."""
    return tuple(f.name for f in INSTRUCTIONS[key].fields if f.kind not in ("flag", "edge", "coil"))


def _find_word(text: str, word: str, lo: int, hi: int) -> int:
    position = text.find(word, lo, hi)
    while position >= 0:
        before = text[position - 1] if position > 0 else " "
        after = text[position + len(word)] if position + len(word) < len(text) else " "
        if not (before.isalnum() or before == "_") and not (after.isalnum() or after == "_"):
            return position
        position = text.find(word, position + 1, hi)
    return -1


def unknown_message(glyph: str, top: str) -> str:
    """LD003's message: a known glyph with nothing above it lacks its name;
    anything else gets the closest drawings."""
    from ..reference import suggestion

    if not top.strip():
        named = recognise(glyph, "Xname".center(len(glyph)))
        if named is not None:
            return f"this {INSTRUCTIONS[named[0]].title} has no name: write it on the line above {glyph.strip('-')!r}"
    shown = glyph if not top.strip() else f"{top.strip()} / {glyph}"
    return f"no instruction is drawn like {shown!r}" + suggestion(glyph, top)
