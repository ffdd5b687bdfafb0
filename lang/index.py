"""One cheap pass over a program that every rule shares.

The index lists the elements in evaluation order (series left to right,
parallel branches top to bottom, rungs top to bottom), groups them by kind,
records for each name every place it is used (which element, which operand,
read or written, in order), every constant written where an operand could be
a name, and every series of every rung. Whole-program rules (a relay never
written, a timer name used twice) then look a name up instead of walking the
tree again. Analyses that several rules need (LDmicro's variable-flag walk,
the timer periods, the selected device) are computed once and kept in
`ProgramIndex.cache`.

The language server re-checks after every edit, so this pass is written for
speed: one walk, no generators per element, tuples for the records; and
after an edit it is brought up to date rather than built again
(`ProgramIndex.replace`: every list is sorted by rung, so the entries of the
rungs an edit touched are one slice of it). `ProgramIndex.view` is the index
of a few rungs, `ProgramIndex.of_names` that of a few names: the incremental
checks (`lang.checks.incremental`) run the rules on them.
"""

from __future__ import annotations

from bisect import bisect_left
from collections.abc import Iterable
from functools import cached_property
from operator import itemgetter
from typing import NamedTuple

from .families import FAMILIES
from .flags import MARKING, Mark, shift_stages
from .flags import marks as marks_of
from .instructions import EOL_KINDS, INSTRUCTIONS
from .labels import token
from .model import Element, Parallel, Program, Series, Span
from .values import is_literal_fast

# Operand kinds that hold variable names (or, for operands, a constant).
_NAME_KINDS = ("bit", "var", "operand", "delay")


def _plan(key: str) -> tuple[tuple[str, str], ...]:
    """(field, access) of the operands of an instruction that may name a
    variable or hold a constant; shift registers are handled apart."""
    plan = []
    for f in INSTRUCTIONS[key].fields:
        if f.kind not in _NAME_KINDS or not f.access:
            continue
        if key == "SPI_WR" and f.name == "send":
            continue  # the text to send, not a variable
        plan.append((f.name, f.access))
    return tuple(plan)


_PLANS = {key: _plan(key) for key in INSTRUCTIONS}
_TABLE_KINDS = ("LOOK_UP_TABLE", "PIECEWISE_LINEAR")


class Use(NamedTuple):
    """One use of a name by one operand of one element."""

    name: str
    rung: int
    element: Element
    field: str  # the operand's field name ("name", "dest", ...; "table" for a LUT/PWL table)
    access: str  # "read", "write", "rw" (both) or "table" (a LUT/PWL table name)

    @property
    def span(self) -> Span | None:
        span = self.element.arg_spans.get(self.field)
        return span if span is not None else self.element.span

    @property
    def reads(self) -> bool:
        return self.access == "read" or self.access == "rw"

    @property
    def writes(self) -> bool:
        return self.access == "write" or self.access == "rw"


class Literal(NamedTuple):
    """A constant written where an operand could also be a name."""

    text: str
    rung: int
    element: Element
    field: str


_new = tuple.__new__  # builds a NamedTuple without its Python-level __new__ (hot loop)


def _stages(element: Element) -> list[tuple[str, str, str]]:
    """The names a shift register uses: name0 is the input the program
    writes; the register reads name0..name(n-2) and writes name1..name(n-1)."""
    args = element.args
    base = token(args.get("name"))
    stages = shift_stages(element)
    if not base or is_literal_fast(base):
        return []
    found = []
    for i in range(stages):
        access = "read" if i == 0 else ("write" if i == stages - 1 else "rw")
        found.append((f"{base}{i}", "name", access))
    return found


class ProgramIndex:
    """Elements in order, by kind, every use of every name, every constant
    operand, every flag LDmicro's variable check gives a name, and every
    series (for the rules about rung shapes)."""

    def __init__(self, program: Program, for_build: bool = False, family: str | None = None):
        self.program = program
        self.for_build = for_build  # the checks run before compiling (LD501 is an error then)
        self.family = family  # compiled for this family (lang.families) rather than the part's
        self.rungs: Iterable[int] = range(len(program.rungs))  # the rungs indexed
        self._empty()
        self.names: dict[str, list[Use]] = self.uses  # every name the program uses (a view's: the program's)
        self.whole = self  # the whole program's index (a view's or a part's: the one it was taken from)
        self._build(program, self.rungs)

    def _empty(self) -> None:
        self.elements: list[tuple[int, Element]] = []
        self.by_kind: dict[str, list[tuple[int, Element]]] = {}
        self.uses: dict[str, list[Use]] = {}  # in order of first use
        self.marks: dict[str, list[Mark]] = {}  # lang.flags, in order of first mark
        self.literals: list[Literal] = []
        self.series: list[tuple[int, Series]] = []  # every series, rung circuits included
        # (rung, series, position) of every end-of-line element or parallel
        # block that something follows in its series (LD201, LD202)
        self.followed: list[tuple[int, Series, int]] = []
        self.cache: dict[str, object] = {}

    def _part(self, program: Program, rungs: Iterable[int]) -> ProgramIndex:
        part = ProgramIndex.__new__(ProgramIndex)
        part.program = program
        part.for_build, part.family = self.for_build, self.family
        part.rungs = rungs
        part._empty()
        part.names = self.names
        part.whole = self.whole
        if "device" in self.__dict__:
            part.__dict__["device"] = self.device
        part._build(program, rungs)
        return part

    def view(self, rungs: Iterable[int]) -> ProgramIndex:
        """The index of some rungs of the program (sorted), with the whole
        program's names for the rules that ask whether a name is used."""
        return self._part(self.program, rungs)

    def of_names(self, names: Iterable[str]) -> ProgramIndex:
        """The uses and marks of some names only, whole."""
        part = self._part(self.program, ())
        part.uses = {name: self.uses[name] for name in names if name in self.uses}
        part.marks = {name: self.marks[name] for name in names if name in self.marks}
        return part

    def replace(self, program: Program, first: int, end: int, before: ProgramIndex,
                part: ProgramIndex | None = None) -> ProgramIndex:
        """Bring the index up to date with `program`, the indexed program with
        rungs first..end-1 read again and the same number of rungs (and the
        same settings). `before` is the old index's view of the rungs among
        them whose content changed (the others only moved); the index of the
        new rungs first..end-1 is returned (`part`, when the caller has it)."""
        if part is None:
            part = self._part(program, range(first, end))
        self.program = program
        self.rungs = range(len(program.rungs))
        self.cache = {}
        lists: list[tuple[list, list, int]] = [(self.elements, part.elements, 0), (self.literals, part.literals, 1),
                                               (self.series, part.series, 0), (self.followed, part.followed, 0)]
        for items, new, at in lists:
            _splice(items, first, end, new, at)
        tables: list[tuple[dict[str, list], dict[str, list], dict[str, list], int]] = [
            (self.by_kind, part.by_kind, before.by_kind, 0), (self.uses, part.uses, before.uses, 1),
            (self.marks, part.marks, before.marks, 2)]
        for table, new_table, old_table, at in tables:
            for key in old_table.keys() | new_table.keys():
                new = new_table.get(key, [])
                found = table.get(key)
                if found is None:
                    if new:
                        table[key] = list(new)
                    continue
                _splice(found, first, end, new, at)
                if not found:
                    del table[key]
        return part

    @property
    def pins_matter(self) -> bool:
        """A part is selected and the program is compiled for it, not to C
        for no part (whose runtime reads and writes the I/O)."""
        return self.device is not None and (self.family is None or bool(FAMILIES[self.family].parts))

    def _build(self, program: Program, rungs: Iterable[int]) -> None:
        # one walk; everything it touches is bound to a local name (hot loop)
        elements, by_kind, uses, marks = self.elements, self.by_kind, self.uses, self.marks
        literals, series, followed = self.literals, self.series, self.followed
        eol_kinds, marking = EOL_KINDS, MARKING
        plans, table_kinds, is_literal_, new = _PLANS, _TABLE_KINDS, is_literal_fast, _new
        element_class, series_class = Element, Series

        def add(element: Element, rung: int) -> None:
            pair = (rung, element)
            elements.append(pair)
            kind = element.kind
            same = by_kind.get(kind)
            if same is None:
                by_kind[kind] = [pair]
            else:
                same.append(pair)
            args = element.args
            if kind in marking:
                for mark in marks_of(rung, element):
                    marked = marks.get(mark.name)
                    if marked is None:
                        marks[mark.name] = [mark]
                    else:
                        marked.append(mark)
            if kind == "SHIFT_REGISTER":
                names = _stages(element)
            else:
                for field, access in plans.get(kind, ()):
                    value = args.get(field)
                    if value.__class__ is not str or not value or value == "(none)":
                        continue  # a numeric delay, an absent operand
                    if is_literal_(value):
                        literals.append(new(Literal, (value, rung, element, field)))
                        continue
                    use = new(Use, (value, rung, element, field, access))
                    found = uses.get(value)
                    if found is None:
                        uses[value] = [use]
                    else:
                        found.append(use)
                if kind not in table_kinds:
                    return
                table = token(args.get("table"))
                if not table:
                    return
                names = [(table, "table", "table")]
            for name, field, access in names:
                use = new(Use, (name, rung, element, field, access))
                found = uses.get(name)
                if found is None:
                    uses[name] = [use]
                else:
                    found.append(use)

        def walk(node, rung: int) -> None:
            # a loop, not recursion (blocks may nest a thousand deep): a block
            # met in a series or a parallel is walked next, and the walk then
            # goes on after it from `stack`'s (block, position), innermost last
            stack: list[tuple[Series | Parallel, int]] = []
            start = 0
            while True:
                inner = None
                cls = node.__class__
                if cls is series_class:
                    items = node.items
                    last = len(items) - 1
                    if start == 0:
                        series.append((rung, node))
                    elif start <= last and items[start - 1].__class__ is not series_class:
                        followed.append((rung, node, start - 1))  # back from a block that something follows
                    for position, item in enumerate(items[start:] if start else items, start):
                        if item.__class__ is element_class:
                            add(item, rung)
                            if position < last and item.kind in eol_kinds:
                                followed.append((rung, node, position))
                        else:
                            inner, after = item, position + 1
                            break
                elif cls is element_class:
                    add(node, rung)
                else:
                    branches = node.branches
                    for position, branch in enumerate(branches[start:] if start else branches, start):
                        if branch.__class__ is element_class:
                            add(branch, rung)
                        else:
                            inner, after = branch, position + 1
                            break
                if inner is not None:
                    stack.append((node, after))
                    node, start = inner, 0
                elif stack:
                    node, start = stack.pop()
                else:
                    return

        all_rungs = program.rungs
        for rung_index in rungs:
            walk(all_rungs[rung_index].circuit, rung_index)

    # --- look-ups ------------------------------------------------------------

    def of_kind(self, *kinds: str) -> list[tuple[int, Element]]:
        """(rung index, element) of the given kinds, in evaluation order."""
        if len(kinds) == 1:
            return self.by_kind.get(kinds[0], [])
        present = [kind for kind in kinds if kind in self.by_kind]
        if len(present) <= 1:
            return self.by_kind[present[0]] if present else []
        wanted = frozenset(present)
        return [pair for pair in self.elements if pair[1].kind in wanted]

    def has_kind(self, *kinds: str) -> bool:
        return any(kind in self.by_kind for kind in kinds)

    @cached_property
    def device(self):
        """The selected part's pin data, or None (no part, or no data for it)."""
        mcu = self.program.settings.mcu
        if not mcu:
            return None
        from .devices import find_device

        return find_device(mcu)



def _splice(items: list, first: int, end: int, new: list, at: int) -> None:
    """Put `new` in place of the entries of rungs first..end-1 of a list
    sorted by rung (`at`: where an entry holds its rung)."""
    key = itemgetter(at)
    low = bisect_left(items, first, key=key)
    high = bisect_left(items, end, lo=low, key=key)
    items[low:high] = new
