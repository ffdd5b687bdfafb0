"""Code actions: the quick fixes the reader and the checks attach to their
diagnostics (a name with a prefix its instruction does not allow is renamed
to each allowed prefix, e.g. `Xlamp` written by a coil -> `Ylamp` or
`Rlamp`; a misspelt part), and structural edits of the drawing (insert,
delete, move an element, a parallel branch around the selection, a new
rung; each rung is drawn again, ide.edits)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from enum import Enum

from lang.diagnostics import Diagnostic
from lang.labels import describe
from lang.loader import TEXT_KIND
from lang.model import Element, Rung
from lang.textform.rungs import UnreadRung

from . import edits
from .document import Document
from .fixes import fix_edits

INSERT_KINDS = ("CONTACTS", "COIL", "TON", "OSR", "CTU", "MOVE")


class Kind(Enum):
    QUICKFIX = "quickfix"
    REWRITE = "rewrite"  # of the element under the cursor
    INSERT = "insert"  # an element, a branch or a rung


@dataclass(frozen=True)
class Action:
    title: str
    kind: Kind
    line_edits: tuple[edits.LineEdit, ...]
    text_edits: tuple[edits.TextEdit, ...] = ()
    preferred: bool = False  # the first of a diagnostic's fixes


def offered(document: Document) -> list[Diagnostic]:
    """The diagnostics whose fixes are offered: the reader's while the text
    has reading errors (a rename must see every use of a name), else the checks'."""
    return document.problems if document.has_errors else document.checks


def quick_fixes(document: Document, diagnostic: Diagnostic) -> list[Action]:
    """The fixes of one of `offered`'s diagnostics as edits (ide.fixes, as
    `ladder check --fix` makes them); those that cannot be made are left out."""
    actions = []
    for position, fix in enumerate(diagnostic.fixes):
        try:
            line_edits, text_edits = fix_edits(fix, document.program, document.text, document.kind)
        except edits.EditError:
            continue
        actions.append(Action(fix.title, Kind.QUICKFIX, tuple(line_edits), tuple(text_edits), position == 0))
    return actions


def selected_elements(document: Document, start: tuple[int, int], end: tuple[int, int]
                      ) -> tuple[int | None, list[Element]]:
    """The rung under the selection from `start` to `end`, (line, column), and
    its elements whose glyph the selection touches (or the element under the cursor)."""
    locator = document.locator
    rung_index = locator.rung_at(start[0])
    if rung_index is None:
        rung_index = locator.rung_at(end[0])
    if rung_index is None:
        return None, []
    rung = document.program.rungs[rung_index]
    if start == end:
        hit = locator.hit(start[0], start[1])
        return rung_index, [hit.element] if hit is not None and hit.element is not None else []
    chosen = []
    for element in rung.elements():
        span = element.span
        if span is None:
            continue
        glyph = locator.glyph_span(element) if document.kind == TEXT_KIND else span
        rows = range(span.line, span.end_line + 1)
        if not any(start[0] <= r <= end[0] for r in rows):
            continue
        if start[0] == end[0] and (glyph.end_col <= start[1] or glyph.col >= end[1]):
            continue
        chosen.append(element)
    return rung_index, chosen


def structural(document: Document, start: tuple[int, int], end: tuple[int, int]) -> list[Action]:
    """The edits of the drawing offered for a selection (a cursor: start == end)."""
    if document.kind != TEXT_KIND:
        return []
    rung_index, chosen = selected_elements(document, start, end)
    if rung_index is None:
        return []
    rung = document.program.rungs[rung_index]
    if isinstance(rung, UnreadRung):
        return []  # redrawn from what could be read, it would lose what could not
    actions: list[Action] = []
    locator, text = document.locator, document.text

    def offer(title: str, kind: Kind, make: Callable[[], Rung | edits.LineEdit]) -> None:
        try:
            new = make()
            edit = new if isinstance(new, edits.LineEdit) else edits.redraw(locator, text, rung_index, new)
        except edits.EditError:
            return
        actions.append(Action(title, kind, (edit,)))

    def insert(kind: str, element: Element, after: bool) -> Callable[[], Rung]:
        return lambda: edits.insert_element(rung, element, edits.new_element(kind), after=after)

    if not rung.is_comment and len(chosen) == 1:
        element = chosen[0]
        what = describe(element)
        offer(f"Delete {what}", Kind.REWRITE, lambda: edits.delete_element(rung, element))
        offer(f"Move {what} left", Kind.REWRITE, lambda: edits.move_element(rung, element, -1))
        offer(f"Move {what} right", Kind.REWRITE, lambda: edits.move_element(rung, element, +1))
        for kind in INSERT_KINDS:
            word = _word(kind)
            offer(f"Insert {word} before {what}", Kind.INSERT, insert(kind, element, False))
            offer(f"Insert {word} after {what}", Kind.INSERT, insert(kind, element, True))
    if not rung.is_comment and chosen:
        around = describe(chosen[0]) if len(chosen) == 1 else f"{len(chosen)} elements"
        offer(f"Add a parallel branch (contact) around {around}", Kind.INSERT,
              lambda: edits.add_parallel(rung, chosen, edits.new_element("CONTACTS")))
        if all(e.spec.eol for e in chosen):
            offer(f"Add a parallel coil beside {around}", Kind.INSERT,
                  lambda: edits.add_parallel(rung, chosen, edits.new_element("COIL")))
    offer("Insert a rung above", Kind.INSERT, lambda: edits.insert_rung(locator, text, rung_index, edits.new_rung()))
    offer("Insert a rung below", Kind.INSERT,
          lambda: edits.insert_rung(locator, text, rung_index + 1, edits.new_rung()))
    offer("Insert a comment rung above", Kind.INSERT,
          lambda: edits.insert_rung(locator, text, rung_index, edits.comment_rung("comment")))
    return actions


def _word(kind: str) -> str:
    return {"CONTACTS": "contact", "COIL": "coil"}.get(kind, kind)
