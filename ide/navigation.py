"""Names across the program: go to definition (where a coil or variable is
written, where a label is), references, document highlight and rename (the
rungs touched are drawn again, ide.edits). The uses come from the checks'
ProgramIndex."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from lang.loader import LD_KIND, TEXT_KIND
from lang.model import Span
from lang.textform.sections import DETAILS, IO, VARS

from . import edits, names
from .document import Document
from .locate import word_at

LABEL_KINDS = {"GOTO": ("LABEL",), "GOSUB": ("SUBPROG",), "LABEL": ("LABEL",), "SUBPROG": ("SUBPROG",),
               "ENDSUB": ("SUBPROG",)}


@dataclass(frozen=True)
class Occurrence:
    """A name or label at a place of the source."""

    name: str
    label: bool  # a GOTO/GOSUB/LABEL name, not a variable's
    span: Span  # of this occurrence


class Access(Enum):
    WRITE = "write"  # a label's definition
    READ = "read"  # a label's use
    TEXT = "text"  # a row of the I/O table, VAR LIST, DETAILS


@dataclass(frozen=True)
class Highlight:
    span: Span
    access: Access


def name_at(document: Document, line: int, col: int) -> Occurrence | None:
    """The name or label at a position."""
    locator = document.locator
    if document.kind == TEXT_KIND and locator.section_at(line) in (IO, VARS, DETAILS):
        return _word(document, line, col)
    hit = locator.hit(line, col, end_inclusive=True)
    if hit is not None and hit.element is not None and hit.field is not None:
        value = hit.element.args.get(hit.field)
        field = hit.element.spec.get_field(hit.field)
        span = hit.element.arg_spans.get(hit.field)
        if not isinstance(value, str) or span is None:
            return None
        if field.kind == "label":
            return Occurrence(value, True, span)
        if names.takes_name(hit.element.kind, hit.field) and names.is_name(value):
            return Occurrence(value, False, span)
        return None
    if document.kind == LD_KIND and hit is None:
        return _word(document, line, col)
    return None


def _word(document: Document, line: int, col: int) -> Occurrence | None:
    word = word_at(document.line(line), col)
    if word and names.known(document.program, document.index, word[2]):
        return Occurrence(word[2], False, Span.at(line, word[0], word[1]))
    return None


def label_places(document: Document, label: str) -> tuple[list[Span], list[Span]]:
    """(definitions: LABEL/SUBPROG, uses: GOTO/GOSUB/ENDSUB) of a label."""
    definitions: list[Span] = []
    uses: list[Span] = []
    for _, element in document.program.elements():
        if element.kind in LABEL_KINDS and element.args.get("label") == label:
            span = element.arg_spans.get("label") or element.span
            if span is None:
                continue
            (definitions if element.kind in ("LABEL", "SUBPROG") else uses).append(span)
    return definitions, uses


def pin_span(document: Document, name: str) -> Span | None:
    assignment = document.program.pins.get(name)
    return assignment.span if assignment is not None else None


def other_rows(document: Document, name: str) -> list[Span]:
    """Occurrences of a name in the I/O table, VAR LIST and DETAILS (text form)."""
    if document.kind != TEXT_KIND:
        span = pin_span(document, name)
        return [span] if span is not None else []
    return [Span.at(number, start, end)
            for number, start, end in edits.names_in_sections(document.locator, name, (IO, VARS, DETAILS))]


def definition(document: Document, target: Occurrence) -> list[Span]:
    """Where a name is written (else its I/O row, else its first use); a label's LABEL or SUBPROG."""
    if target.label:
        return label_places(document, target.name)[0]
    uses = names.uses_of(document.index, target.name)
    spans = [u.span for u in uses.writes if u.span is not None]
    if not spans:
        pin = pin_span(document, target.name)
        spans = [pin] if pin is not None else [u.span for u in uses.uses[:1] if u.span is not None]
    return spans


def references(document: Document, target: Occurrence, declaration: bool) -> list[Span]:
    """Every use, in order; with `declaration`, the definitions of a label, the rows of a name."""
    if target.label:
        definitions, uses = label_places(document, target.name)
        spans = (definitions if declaration else []) + uses
    else:
        spans = [u.span for u in names.uses_of(document.index, target.name).uses if u.span is not None]
        if declaration:
            spans += other_rows(document, target.name)
    return sorted(set(spans))


def highlights(document: Document, target: Occurrence) -> list[Highlight]:
    if target.label:
        definitions, uses = label_places(document, target.name)
        return [Highlight(s, Access.WRITE) for s in definitions] + [Highlight(s, Access.READ) for s in uses]
    found = [Highlight(use.span, Access.WRITE if use.writes else Access.READ)
             for use in names.uses_of(document.index, target.name).uses if use.span is not None]
    return found + [Highlight(span, Access.TEXT) for span in other_rows(document, target.name)]


def renamable(document: Document) -> None:
    """EditError when the document cannot be renamed in: a rename must see every use."""
    if document.has_errors:
        raise edits.EditError("fix the errors in this file before renaming")


def rename(document: Document, old: str, new: str) -> tuple[list[edits.LineEdit], list[edits.TextEdit]]:
    """EditError when it cannot be made."""
    renamable(document)
    return edits.rename(document.program, document.locator, document.text, old, new, document.kind)
