"""Checking a program again after an edit, doing again only what the edit can
change (the language server checks after every keystroke).

`Checker.check(program, moved)` gives what `check_program(program)` gives
(tests/test_checks_incremental.py compares them after random edits). It keeps
the last program's symbol table (`ProgramIndex`) and its diagnostics, split by
the rules' scopes (`common.RUNGS`, `NAMES`, `PROGRAM`). For the next program:

* a rung that is the same object as the one at its place before is unchanged;
  one the reader moved (`moved`: id(new rung) -> (old rung, lines moved)) has
  the old rung's circuit, whose elements the reader moved in place (their
  positions are the new ones, in the index too); every other rung is *changed*;
* the index replaces the entries of the changed rungs (one slice of each of
  its lists);
* the RUNGS rules run on the index of the changed rungs, before and after: the
  diagnostics the old rungs gave are taken out of the kept ones, the new ones
  put in; the same for the NAMES rules on the index of the names the changed
  rungs use (old and new uses); the kept diagnostics of moved rungs move with
  them. When a name comes into use or goes out of it, the RUNGS rules run
  again on the unchanged rungs that have a diagnostic on an operand holding a
  name a fix could offer to rename to it (a rename is offered only to an
  unused name, on the operand's place): of a name used by a thousand rungs,
  the few with a diagnostic there, and none of them indexed again;
* the NAMES rules' diagnostics of the names an edit checked again are kept
  with the program they were found on: the next edit, when it checks the
  same names again (the same rung edited again without a name changing, or
  a name typed over and back), takes them as the old ones rather than
  running the rules on the old program (a name a thousand rungs use costs
  one run of its rules, not two);
* the PROGRAM rules run on the whole index, every time.

An edit that adds, removes or changes a GOTO, LABEL or subroutine element
changes the order the rungs run in, which NAMES rules may follow (reading the
program's jumps from `index.whole`): the program is checked whole.

A row of the I/O table changed: the name's NAMES rules run again (no RUNGS
rule reads the pins, so the rungs that use the name are not checked again:
a name shared by thousands of rungs, one row edited, costs one name).
Anything else (other settings or variable sizes, another number of rungs, most rungs changed) is checked whole.
"""

from __future__ import annotations

from bisect import bisect_right
from collections import Counter
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from itertools import compress, count
from operator import is_not
from types import ModuleType

from ..config import NONE, Severities
from ..diagnostics import Diagnostic, Related
from ..index import ProgramIndex
from ..instructions import JUMPS
from ..model import Program, Rung, Span
from . import RULES
from .common import NAMES, PROGRAM, RUNGS, offering


def checks_of(rule: ModuleType) -> dict[str, Callable[[Program, ProgramIndex], list[Diagnostic]]]:
    """A rule's check functions by scope: its `check` at its `SCOPE`, or, for a
    rule whose diagnostics depend on different things, its `CHECKS`."""
    return getattr(rule, "CHECKS", None) or {getattr(rule, "SCOPE", PROGRAM): rule.check}


BY_SCOPE = {scope: tuple(check for rule in RULES for at, check in checks_of(rule).items() if at == scope)
            for scope in (RUNGS, NAMES, PROGRAM)}


def run(scope: str, program: Program, index: ProgramIndex) -> list[Diagnostic]:
    found: list[Diagnostic] = []
    for check in BY_SCOPE[scope]:
        found.extend(check(program, index))
    return found


def position(diagnostic: Diagnostic) -> tuple:
    """Sort key: source position (diagnostics without one first), then code."""
    span = diagnostic.span
    if span is None:
        return (-1, -1, diagnostic.code, diagnostic.message)
    return (span.line, span.col, diagnostic.code, diagnostic.message)


def same_context(old: Program, new: Program) -> bool:
    """Everything a RUNGS or NAMES rule reads besides the rungs and the pins
    is unchanged (a name's pin counts for the name's NAMES rules only:
    `_Edit.pinned`)."""
    return old.settings == new.settings and old.var_sizes == new.var_sizes and len(old.rungs) == len(new.rungs)


@dataclass
class _Edit:
    changed: list[int] = field(default_factory=list)  # rung numbers
    pinned: set[str] = field(default_factory=set)  # names whose I/O table row changed
    # the moved rungs' old lines, sorted: first lines, last lines, how far each moved
    starts: list[int] = field(default_factory=list)
    ends: list[int] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)

    def shifted(self, diagnostic: Diagnostic) -> Diagnostic:
        """The diagnostic of a rung that moved, at its new place (one that
        did not move is returned as it is)."""
        if not self.starts:
            return diagnostic
        span = diagnostic.span
        if (span is None or span.line < self.starts[0]) and \
                all(related.span.line < self.starts[0] for related in diagnostic.related):
            return diagnostic
        # built, not `replace`d: a line added above a thousand diagnostics moves them all
        return Diagnostic(diagnostic.code, diagnostic.severity, diagnostic.message,
                          self._move(span) if span is not None else None,
                          tuple(Related(self._move(r.span), r.message) for r in diagnostic.related)
                          if diagnostic.related else (), diagnostic.fixes)

    def _move(self, span: Span) -> Span:
        at = bisect_right(self.starts, span.line) - 1
        if at < 0 or span.line > self.ends[at]:
            return span
        return span.shifted(self.lines[at])


class Checker:
    def __init__(self, for_build: bool = False, family: str | None = None):
        self.for_build = for_build
        self.family = family
        self.index: ProgramIndex | None = None  # the last program's
        self._rungs: list[Diagnostic] = []  # the RUNGS rules' diagnostics of the last program
        self._names: list[Diagnostic] = []  # the NAMES rules'
        # the names the last edit checked again, the program it made, and what the NAMES rules
        # gave on them: the next edit of the same rung (the same names) takes them as the old ones
        self._renamed: tuple[frozenset[str], Program, list[Diagnostic]] | None = None
        self.last = ""  # how the last check went: "whole" or "edit" (tests, benchmarks)

    def check(self, program: Program, moved: dict[int, tuple[Rung, int]] | None = None,
              severities: Severities = NONE) -> list[Diagnostic]:
        """Every rule's diagnostics at the chosen severities, sorted by position."""
        index = self.index
        edit = _edit(index.program, program, moved or {}) if index is not None else None
        if index is None or edit is None:
            self._whole(program)
        else:
            self._edit(index, program, edit)
        assert self.index is not None
        found = self._rungs + self._names + run(PROGRAM, program, self.index)
        found = severities.apply(found, building=self.for_build)
        found.sort(key=position)
        return found

    def _whole(self, program: Program) -> None:
        self.last = "whole"
        self.index = index = ProgramIndex(program, self.for_build, self.family)
        self._rungs = run(RUNGS, program, index)
        self._names = run(NAMES, program, index)
        self._renamed = None

    def _edit(self, index: ProgramIndex, program: Program, edit: _Edit) -> None:
        self.last = "edit"
        old_program = index.program
        changed = edit.changed
        before = index.view(changed)
        after = index._part(program, changed)
        if _jumps(before) != _jumps(after):
            # the order the rungs run in changed: a NAMES rule that follows it (LD133) is
            # a function of each name's uses and of that order, so every name is checked again
            self._whole(program)
            return
        names = _names(before) | _names(after) | edit.pinned
        came_or_went = {name for name in names
                        if (name in index.uses) != (len(index.uses.get(name, ())) - len(before.uses.get(name, ()))
                                                    + len(after.uses.get(name, ())) > 0)}
        kept_rungs = [edit.shifted(diagnostic) for diagnostic in self._rungs]
        # unchanged rungs whose diagnostics may offer a rename to a name that came or went:
        # their RUNGS rules run again, on a view of them before and after (not indexed again)
        offered = sorted(_offering(index, came_or_went, kept_rungs) - set(changed)) if came_or_went else []
        gone_rungs = Counter(run(RUNGS, old_program, before))
        if offered:
            gone_rungs.update(run(RUNGS, old_program, index.view(offered)))
        names_key = frozenset(names)
        last = self._renamed
        if last is not None and last[0] == names_key and last[1] is old_program:
            gone_names = Counter(map(edit.shifted, last[2]))
        else:
            gone_names = Counter(run(NAMES, old_program, index.of_names(names)))

        if changed:
            contiguous = changed[-1] - changed[0] + 1 == len(changed)
            index.replace(program, changed[0], changed[-1] + 1, before, after if contiguous else None)
        else:
            index.program, index.rungs, index.cache = program, range(len(program.rungs)), {}
        found = run(RUNGS, program, after)
        if offered:
            found += run(RUNGS, program, index.view(offered))
        self._rungs = _without(kept_rungs, gone_rungs) + found
        found_names = run(NAMES, program, index.of_names(names))
        self._renamed = (names_key, program, found_names)
        self._names = _without(map(edit.shifted, self._names), gone_names) + found_names


def _edit(old: Program, new: Program, moved: dict[int, tuple[Rung, int]]) -> _Edit | None:
    """How `new` differs from `old` rung by rung, or None to check it whole."""
    if not same_context(old, new):
        return None
    edit = _Edit()
    # the rungs that are not the same objects, found without a Python loop over all of them
    for number in compress(count(), map(is_not, new.rungs, old.rungs)):
        rung, was = new.rungs[number], old.rungs[number]
        origin = moved.get(id(rung))
        if origin is not None and origin[0] is was and was.span is not None:
            # moved, or read again after the reader had moved its circuit in place (versions
            # read but not checked): what it gave is where its elements were moved to
            edit.starts.append(was.span.line)
            edit.ends.append(was.span.end_line)
            edit.lines.append(origin[1])
            if rung.circuit is not was.circuit:
                edit.changed.append(number)
        else:
            edit.changed.append(number)
    if 2 * len(edit.changed) > len(new.rungs):
        return None
    if old.pins != new.pins:
        edit.pinned = {name for name in old.pins.keys() | new.pins.keys() if old.pins.get(name) != new.pins.get(name)}
    return edit


def _jumps(index: ProgramIndex) -> list[tuple[int, str, str]]:
    """The GOTOs, LABELs and subroutine elements of an index's rungs and their labels."""
    return sorted((rung, element.kind, str(element.args.get("label"))) for kind in (*JUMPS, "LABEL")
                  for rung, element in index.by_kind.get(kind, ()))


def _names(index: ProgramIndex) -> set[str]:
    return index.uses.keys() | index.marks.keys()


def _offering(index: ProgramIndex, names: set[str], diagnostics: list[Diagnostic]) -> set[int]:
    """The rungs (numbers) with a diagnostic (among `diagnostics`, at their
    current places) on an operand that holds a name a fix may offer to rename
    to one of `names`: a rename is offered on the operand's own place, and a
    name shared by a thousand rungs has a diagnostic in few of them."""
    offered = [use for name in names for old in offering(name)
               for use in (*index.uses.get(old, ()), *index.marks.get(old, ()))]
    if not offered:
        return set()
    places = {diagnostic.span for diagnostic in diagnostics}
    places.discard(None)
    return {use.rung for use in offered
            if use.element.span in places or not places.isdisjoint(use.element.arg_spans.values())}


def _without(found: Iterable[Diagnostic], gone: Counter) -> list[Diagnostic]:
    """`found` without the diagnostics in `gone` (as many times as they are
    there; computed on the old rungs, whose moved elements are already at
    their new places, as `found` is)."""
    if not gone:
        return list(found)
    kept = []
    for diagnostic in found:
        if gone[diagnostic] > 0:
            gone[diagnostic] -= 1
            continue
        kept.append(diagnostic)
    return kept
