"""The program model every reader produces and every tool consumes.

A program is a list of rungs; a rung is a series circuit; series hold elements
and parallels, parallels hold elements and series (LDmicro's own shape, kept
normalised: no one-child parallel, no series directly inside a series).
Source ranges never take part in equality, so a program read from a drawing
equals the same program read from a `.ld` file.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import NamedTuple

from .instructions import INSTRUCTIONS, Instruction


class Span(NamedTuple):
    """A source range: 0-based lines, 0-based character columns, end exclusive.

    A named tuple, not a dataclass: a program holds a dozen spans a rung and
    the reader makes them by the ten thousand (a frozen dataclass is built
    four times slower, and with a __dict__ it would take 40 bytes more)."""

    line: int
    col: int
    end_line: int
    end_col: int

    @staticmethod
    def at(line: int, col: int, end_col: int | None = None) -> Span:
        return Span(line, col, line, col + 1 if end_col is None else end_col)

    def shifted(self, lines: int) -> Span:
        """The same range `lines` lines further down (up when negative)."""
        return Span(self.line + lines, self.col, self.end_line + lines, self.end_col)

    def union(self, other: Span | None) -> Span:
        if other is None:
            return self
        start = min((self.line, self.col), (other.line, other.col))
        end = max((self.end_line, self.end_col), (other.end_line, other.end_col))
        return Span(start[0], start[1], end[0], end[1])


class Origin:
    """The lines a circuit has moved since it was read: its nodes keep their
    positions as read and add this. A line added above a rung moves every
    rung below it; with an origin that costs one addition a rung, not one
    new span per element (lang.textform.reader.move_circuit)."""

    __slots__ = ("line",)

    def __init__(self) -> None:
        self.line = 0


def _moved(span: Span | None, lines: int) -> Span | None:
    return span if span is None else new_span(Span, (span[0] + lines, span[1], span[2] + lines, span[3]))


# a Span without its Python-level __new__ (an open places every element, an edit moves rungs):
# new_span(Span, (line, col, end_line, end_col))
new_span = tuple.__new__


class _Placed:
    """A node's `span` as read, plus its circuit's origin (None: not moved)."""

    __slots__ = ()
    _span: Span | None
    _origin: Origin | None

    @property
    def span(self) -> Span | None:
        origin = self._origin
        if origin is None or not origin.line:
            return self._span
        return _moved(self._span, origin.line)

    @span.setter
    def span(self, span: Span | None) -> None:
        origin = self._origin
        # the subclasses hold the slot (Element a __dict__), which mypy cannot see here
        self._span = span if origin is None or not origin.line else _moved(span, -origin.line)  # type: ignore[misc]


@dataclass(init=False)
class Element(_Placed):
    """One instruction: `kind` is its key in the instruction table, `args` its
    operands by field name, in the table's field order. `span` and
    `arg_spans` (where each drawn operand sits, for hover and rename) take no
    part in equality."""

    kind: str
    args: dict[str, object]

    def __init__(self, kind: str, args: dict[str, object], span: Span | None = None,
                 arg_spans: dict[str, Span] | None = None):
        self.kind = kind
        self.args = args
        self._span = span
        self._arg_spans = {} if arg_spans is None else arg_spans
        self._origin = None

    @property
    def arg_spans(self) -> dict[str, Span]:
        """The operands' positions; of a moved element, a copy at the new place."""
        origin = self._origin
        if origin is None or not origin.line:
            return self._arg_spans
        lines = origin.line
        return {key: new_span(Span, (at[0] + lines, at[1], at[2] + lines, at[3]))
                for key, at in self._arg_spans.items()}

    @arg_spans.setter
    def arg_spans(self, spans: dict[str, Span]) -> None:
        origin = self._origin
        self._arg_spans = spans if origin is None or not origin.line else \
            {key: _moved(at, -origin.line) for key, at in spans.items()}  # type: ignore[misc]

    @property
    def spec(self) -> Instruction:
        return INSTRUCTIONS[self.kind]


@dataclass(init=False)
class Series(_Placed):
    __slots__ = ("items", "_span", "_origin")
    items: list[Node]

    def __init__(self, items: list[Node], span: Span | None = None):
        self.items = items
        self._span = span
        self._origin = None


@dataclass(init=False)
class Parallel(_Placed):
    __slots__ = ("branches", "_span", "_origin")
    branches: list[Node]

    def __init__(self, branches: list[Node], span: Span | None = None):
        self.branches = branches
        self._span = span
        self._origin = None


Node = Element | Series | Parallel


@dataclass(slots=True)
class Rung:
    circuit: Series
    span: Span | None = field(default=None, compare=False, repr=False)

    @property
    def is_comment(self) -> bool:
        items = self.circuit.items
        return bool(items) and isinstance(items[0], Element) and items[0].kind == "COMMENT"

    def elements(self) -> Iterator[Element]:
        return iter_elements(self.circuit)


@dataclass
class Settings:
    """Program-wide settings, with LDmicro's defaults for a new program."""

    mcu: str | None = None
    cycle_us: int = 10000
    crystal_hz: int = 16000000
    baud: int = 9600
    cycle_timer: int = 1
    cycle_duty: bool = False
    config_word: int = 0
    spi_rate: int = 1000000
    i2c_rate: int = 100000
    compiled: str | None = None
    compiler: str | None = None
    # LDmicro file dialect the program came from ("0.1", "0.2", or "" for a bare
    # `LDmicro` header, read as 0.2); it decides defaults such as the timer
    # adjust of old files and how a .ld is written
    ld_version: str = "0.2"
    # where the part is named (the header line, the MICRO= line), for diagnostics
    mcu_span: Span | None = field(default=None, compare=False, repr=False)


@dataclass
class PinAssignment:
    name: str
    pin: int | str  # a package pin number, or a port-bit name such as "PD2"
    modbus_slave: int = 0
    modbus_register: int = 0
    span: Span | None = field(default=None, compare=False, repr=False)

    @property
    def assigned(self) -> bool:
        """A pin is given: LDmicro writes pin 0 for a name with none (which
        may still have a Modbus address)."""
        return str(self.pin).strip() not in ("", "0", "None")


@dataclass(frozen=True)
class PropertyLine:
    """A line of the PROPERTIES section as written, and where (0-based)."""

    text: str
    line: int = field(default=-1, compare=False)


@dataclass
class Program:
    settings: Settings = field(default_factory=Settings)
    rungs: list[Rung] = field(default_factory=list)
    pins: dict[str, PinAssignment] = field(default_factory=dict)
    var_sizes: dict[str, int] = field(default_factory=dict)
    pullups: dict[str, int] = field(default_factory=dict)
    # what follows a name on its VAR LIST line: LDmicro 5.4 writes " \tNow not used !!!" (or its
    # translation) for a variable its last compile did not allocate; kept as written
    var_notes: dict[str, str] = field(default_factory=dict)
    # the text form's PROPERTIES section, for `ladder verify` (lang/properties.py reads it)
    properties: list[PropertyLine] = field(default_factory=list)

    def elements(self) -> Iterator[tuple[int, Element]]:
        """Every element with the index of its rung, in evaluation order."""
        for index, rung in enumerate(self.rungs):
            for element in rung.elements():
                yield index, element


def iter_elements(node: Node) -> Iterator[Element]:
    """Elements of a circuit in evaluation order: series left to right,
    parallel branches top to bottom."""
    # the nodes still to visit on a list, next last: blocks may nest a thousand deep
    stack = [node]
    while stack:
        node = stack.pop()
        if isinstance(node, Element):
            yield node
        else:
            stack.extend(reversed(children(node)))


def normalise(node: Node) -> Node:
    """LDmicro's normal form: no one-child parallel or series inside a parallel,
    no series directly inside a series, no empty subcircuits."""
    if isinstance(node, Element):
        return node
    # (block, its children still to normalise, its normal children so far),
    # innermost last: a loop, not recursion, as blocks may nest a thousand deep
    frames: list[tuple[Series | Parallel, Iterator[Node], list[Node]]] = [(node, iter(children(node)), [])]
    while True:
        block, rest, kept = frames[-1]
        for child in rest:
            if isinstance(child, Element):
                kept.append(child)  # all _keep does with an element, in a series or a parallel
            else:
                frames.append((child, iter(children(child)), []))
                break
        else:
            frames.pop()
            done = _closed(block, kept)
            if not frames:
                return done
            parent, _, siblings = frames[-1]
            _keep(parent, siblings, done)


def children(block: Series | Parallel) -> list[Node]:
    return block.items if isinstance(block, Series) else block.branches


def _closed(block: Series | Parallel, kept: list[Node]) -> Node:
    """The block with its normal children; a parallel of one branch is that branch."""
    if isinstance(block, Series):
        return Series(kept, block.span)
    return kept[0] if len(kept) == 1 else Parallel(kept, block.span)


def _keep(parent: Series | Parallel, kept: list[Node], child: Node) -> None:
    """Adds a normal child to its parent's: a series's items are spliced into
    a series, a parallel's branches into a parallel, a one-item series stands
    for its item in a parallel, and empty blocks go."""
    if isinstance(parent, Series):
        if isinstance(child, Series):
            kept.extend(child.items)
        elif not (isinstance(child, Parallel) and not child.branches):
            kept.append(child)
        return
    if isinstance(child, Series) and len(child.items) == 1:
        child = child.items[0]
    if isinstance(child, Series) and not child.items:
        return
    if isinstance(child, Parallel):
        kept.extend(child.branches)
    else:
        kept.append(child)


def rung_circuit(node: Node) -> Series:
    """The normalised root series of a rung."""
    node = normalise(node)
    if isinstance(node, Series):
        return node
    return Series([node], node.span)
