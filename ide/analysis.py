"""The analysis of a document being edited, one version after another: the
text read and checked, the symbol table and the locator built on it, and the
features' results kept per rung while the rung is unchanged, shared by all
the versions of a document. The language server keeps one per open
document's version (lsp/documents.py, which adds the document's URI, version
and positions in the client's encoding)."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from functools import cached_property
from itertools import compress, count
from operator import is_not
from typing import Any, TypeVar, cast

from lang import codes
from lang.checks import Checker
from lang.config import NONE
from lang.diagnostics import ERROR, Diagnostic
from lang.index import ProgramIndex
from lang.loader import checkable, checked
from lang.model import Program, Rung

from .locate import Locator

T = TypeVar("T")

# rungs a whole-document answer keeps joined together (`Analysis.per_run`): an edit of one
# rung of 18,000 joins 64 rungs' parts and 282 runs', not 18,000 parts
RUN = 64


@dataclass(frozen=True)
class _Run:
    """A run of consecutive rungs' joined result, valid while the rungs at
    those places are the same objects, and, shifted, while they hold the
    same circuits moved by the same number of lines."""

    indexes: tuple[int, ...]
    ids: tuple[int, ...]
    rungs: tuple[Rung, ...]  # kept alive, so that no other rung or circuit takes one of their ids
    circuits: tuple[int, ...]
    firsts: tuple[int, ...] | None  # the rungs' first lines, when the result can be shifted
    value: object


class RungResults:
    """The per-rung results of one document's features (semantic tokens,
    symbols, folding), shared by all its versions: (feature, id(rung)) ->
    (rung, value), valid while that rung object is in the program (the reader
    keeps a rung's object while its lines stay as they are, where they are).
    A rung the reader moved up or down is a new object; its result is the old
    one's shifted, worked out when a feature first asks for it, so an edit
    that moves a thousand rungs costs nothing until then."""

    # results kept per rung of the program before the dead ones are dropped
    SLACK = 8

    def __init__(self, shifters: dict[str, Callable[[Any, int], Any]]):
        self.values: dict[tuple[str, int], tuple[Rung, object]] = {}
        self.shifters = shifters
        # (feature, position of the run's first rung in the rungs asked for) -> that run
        self.runs: dict[tuple[str, int], _Run] = {}

    def get(self, feature: str, rung: Rung, origin: tuple[Rung, int] | None, compute: Callable[[], T]) -> T:
        """The feature's result for the rung: kept, the shifted one of the rung it was moved from, or computed."""
        key = (feature, id(rung))
        found = self.values.get(key)
        if found is not None and found[0] is rung:
            return cast(T, found[1])
        shift = self.shifters.get(feature)
        if origin is not None and shift is not None:
            before = self.values.get((feature, id(origin[0])))
            if before is not None and before[0] is origin[0]:
                shifted: T = shift(before[1], origin[1])
                self.values[key] = (rung, shifted)
                return shifted
        value = compute()
        self.values[key] = (rung, value)
        return value

    def prune(self, program: Program, keep: dict[int, tuple[Rung, int]]) -> None:
        """Drops the results of rungs gone (but those a moved rung still
        takes its result from), once there are many."""
        if len(self.values) <= self.SLACK * (len(program.rungs) + 100):
            return
        live = {id(rung): rung for rung in program.rungs}
        live.update((id(old), old) for old, _ in keep.values())
        self.values = {key: value for key, value in self.values.items() if live.get(key[1]) is value[0]}


class Analysis:
    """Everything known about one version of one document: its text read
    (by the document's `IncrementalReader`) and checked on demand (by the
    document's `Checker`, which checks again only what changed since the
    program it checked last), its symbol table and locator, and the results
    the features keep per rung (`memo`, shared by the document's versions)
    or for this exact text (`once`)."""

    def __init__(self, kind: str, text: str, program: Program, problems: list[Diagnostic],
                 checker: Checker | None = None, moved: dict[int, tuple[Rung, int]] | None = None):
        self.kind = kind
        self.text = text
        self.program = program
        self.problems = problems  # the reader's
        self.too_large = False  # not analysed: no checks
        self.severities = NONE  # the project's and the editor's choices (lang/config.py)
        self.memo = RungResults({})  # the document's, shared with its other versions
        # rung id -> (the rung of an earlier version it was moved from, by how many lines), for
        # the rungs whose results have not followed them yet
        self.moved_from: dict[int, tuple[Rung, int]] = {}
        # the text's lines and its sections' titles, as the reader split it (None: split here)
        self.split: tuple[list[str], list[tuple[str, int]]] | None = None
        self.results: dict[str, object] = {}  # whole-document results for this exact text
        self._checker = checker or Checker()  # the document's: it knows the program checked last
        # rungs moved since the program the checker checked last (ide.incremental's `moved`)
        self.moved = moved or {}
        # the locator of the version read before, if it had one, and the rungs the reader
        # moved since: the rungs' lines carry over
        self._previous_locator: tuple[Locator, dict[int, tuple[Rung, int]]] | None = None

    def per_rung(self, feature: str, index: int, compute: Callable[[int], T]) -> T:
        """The feature's result for rung `index`, kept while the rung is unchanged."""
        rung = self.program.rungs[index]
        return self.memo.get(feature, rung, self.moved_from.get(id(rung)), lambda: compute(index))

    def per_run(self, feature: str, indexes: Sequence[int], compute: Callable[[Sequence[int]], T],
                shift: Callable[[T, int], T] | None = None) -> Iterator[T]:
        """The feature's results for the rungs `indexes` (in order) in runs of
        `RUN`, `compute(run)` each, one run at a time (the warm-up works them
        out between two looks at the input), kept while every rung of the run
        is the same object at the same index: the whole-document answers
        (outline, folding, semantic tokens) join an unchanged run's part as it
        was. With `shift(result, lines)`, a run whose rungs the reader moved
        (new rungs, same circuits) all by the same number of lines, by a line
        added or removed above them, takes its result shifted."""
        rungs = self.program.rungs
        runs = self.memo.runs
        for start in range(0, len(indexes), RUN):
            run = tuple(indexes[start:start + RUN])
            members = tuple([rungs[i] for i in run])
            ids = tuple(map(id, members))
            kept = runs.get((feature, start))
            if kept is None or kept.ids != ids or kept.indexes != run:
                circuits = tuple([id(rung.circuit) for rung in members])
                firsts = self._firsts(run) if shift is not None else None
                delta = None
                if kept is not None and kept.indexes == run and kept.circuits == circuits:
                    delta = _common_delta(kept.firsts, firsts)
                value = compute(run) if kept is None or delta is None or shift is None else \
                    shift(cast(T, kept.value), delta)
                kept = runs[feature, start] = _Run(run, ids, members, circuits, firsts, value)
            yield cast(T, kept.value)

    def _firsts(self, run: Sequence[int]) -> tuple[int, ...] | None:
        """The first lines of the rungs (None: one is not drawn)."""
        found = []
        for index in run:
            lines = self.locator.rung_lines(index)
            if lines is None:
                return None
            found.append(lines[0])
        return tuple(found)

    def once(self, feature: str, compute: Callable[[], T]) -> T:
        """A whole-document result, computed once per text."""
        if feature not in self.results:
            self.results[feature] = compute()
        return cast(T, self.results[feature])

    @cached_property
    def lines(self) -> list[str]:
        return self.split[0] if self.split is not None else self.text.splitlines()

    @property
    def has_errors(self) -> bool:
        return any(p.severity == ERROR for p in self.problems)

    @cached_property
    def checks(self) -> list[Diagnostic]:
        """The checks' diagnostics, as `ladder check` gives them: for a
        program read without errors, or whose only errors are in rungs that
        could not be read (lang.loader.checkable)."""
        if self.too_large or any(p.code == codes.UNREADABLE for p in self.problems) or \
                not checkable(self.program, self.problems):
            return []
        found = self._checker.check(self.program, self.moved, self.severities)
        return checked(self.program, found) if self.has_errors else found

    @property
    def checked(self) -> bool:
        return "checks" in self.__dict__

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return self.problems + self.checks

    @cached_property
    def index(self) -> ProgramIndex:
        """The symbol table: the checker's, brought up to this program by
        checking it (the checks cost what changed since the program checked
        last; a new table costs every rung, 200 ms for 18,000: a hover asked
        before an edit's diagnostics are due must not pay that). It is brought
        up to date in place by the next check: use it at once."""
        _ = self.checks  # brings the checker's table up to this program
        index = self._checker.index
        if index is not None and index.program is self.program:
            return index
        return ProgramIndex(self.program)

    def follow(self, before: Analysis, moved: dict[int, tuple[Rung, int]]) -> None:
        """This version's locator is to take the rungs' lines from the
        locator of `before` (the version read before it, of the same kind),
        or from the one `before` was to take them from when it built none:
        a version no feature located anything in (typing, its diagnostics
        not due yet) leaves the next one a locator to follow, not 18,000 rungs
        to walk. `moved`: the rungs the reader moved since `before`."""
        if "locator" in before.__dict__:
            self._previous_locator = (before.locator, moved)
        elif before._previous_locator is not None:
            older, moved_before = before._previous_locator
            self._previous_locator = (older, still_moved(moved_before, self.program, moved, before.program))

    @cached_property
    def locator(self) -> Locator:
        previous, self._previous_locator = self._previous_locator, None
        titles = self.split[1] if self.split is not None else None
        if previous is None:
            return Locator(self.program, self.lines, self.kind, titles=titles)
        return Locator(self.program, self.lines, self.kind, *previous, titles=titles)

    def line(self, number: int) -> str:
        lines = self.lines
        return lines[number] if 0 <= number < len(lines) else ""


def _common_delta(before: tuple[int, ...] | None, now: tuple[int, ...] | None) -> int | None:
    """The lines every rung moved by, None unless all moved by as many."""
    if before is None or now is None or len(before) != len(now) or not now:
        return None
    delta = now[0] - before[0]
    return delta if all(b - a == delta for a, b in zip(before, now)) else None


def still_moved(earlier: dict[int, tuple[Rung, int]], program: Program,
                 moved: dict[int, tuple[Rung, int]], previous: Program | None = None) -> dict[int, tuple[Rung, int]]:
    """Where each rung of `program` whose results have not followed it comes
    from: the rungs the reader just moved (from wherever their rung of the
    version before, `previous`, came from), and those the version before had
    still to follow and that stayed as they were. The answers' runs shift
    without their rungs' results following, so after a line added above
    9,000 rungs `earlier` holds them all, version after version: when the
    rungs are as many as before, the ones that changed are found without a
    Python loop over all of them."""
    found = {}
    if earlier and previous is not None and len(previous.rungs) == len(program.rungs):
        found = dict(earlier)
        old_rungs = previous.rungs
        for index in compress(count(), map(is_not, program.rungs, old_rungs)):
            found.pop(id(old_rungs[index]), None)
    elif earlier:
        for rung in program.rungs:
            origin = earlier.get(id(rung))
            if origin is not None:
                found[id(rung)] = origin
    for new, (old, delta) in moved.items():
        before = earlier.get(id(old))
        found[new] = (before[0], before[1] + delta) if before is not None else (old, delta)
    return found


def moved_since(earlier: dict[int, tuple[Rung, int]], program: Program,
                moved: dict[int, tuple[Rung, int]], previous: Program | None = None) -> dict[int, tuple[Rung, int]]:
    """The rungs of `program` moved since the program checked last, given
    those the previous version (read, never checked), `previous`, had moved,
    `earlier`, and those the reader moved since it. A rung read again after
    it had moved is given too, with the checked rung whose circuit the reader
    had moved in place: the checker knows it by its other circuit."""
    if not earlier:
        return moved
    before = previous.rungs if previous is not None and len(previous.rungs) == len(program.rungs) else None
    found = {}
    for number, rung in enumerate(program.rungs):
        step = moved.get(id(rung))
        if step is None:
            origin = earlier.get(id(rung))  # the same rung as in the previous version
            if origin is None and before is not None and before[number] is not rung:
                origin = earlier.get(id(before[number]))  # read again after moving
        else:
            was = earlier.get(id(step[0]))
            if was is None:
                origin = step
            elif step[0].circuit is was[0].circuit:
                origin = (was[0], was[1] + step[1])
            else:
                origin = was  # read again since the check: this move is not its checked circuit's
        if origin is not None:
            found[id(rung)] = origin
    return found
