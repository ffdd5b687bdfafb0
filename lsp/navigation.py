"""Names across the program: go to definition (where a coil or variable is
written, where a label is), references, document highlight and rename (the
rungs touched are drawn again, ide.edits). The uses come from the checks'
ProgramIndex."""

from __future__ import annotations

from lsprotocol import types

from ide import edits, names
from ide.locate import word_at
from lang.model import Span
from lang.textform.sections import DETAILS, IO, VARS

from .documents import LADDER, LD
from .protocol import UserError

LABEL_KINDS = {"GOTO": ("LABEL",), "GOSUB": ("SUBPROG",), "LABEL": ("LABEL",), "SUBPROG": ("SUBPROG",),
               "ENDSUB": ("SUBPROG",)}


def name_at(analysis, line: int, col: int) -> tuple[str, str, Span] | None:
    """(name, "name" or "label", span of the occurrence) at a position."""
    locator = analysis.locator
    text = analysis.line(line)
    if analysis.kind == LADDER and locator.section_at(line) in (IO, VARS, DETAILS):
        word = word_at(text, col)
        if word and _known(analysis, word[2]):
            return word[2], "name", Span.at(line, word[0], word[1])
        return None
    hit = locator.hit(line, col, end_inclusive=True)
    if hit is not None and hit.element is not None and hit.field is not None:
        value = hit.element.args.get(hit.field)
        field = hit.element.spec.get_field(hit.field)
        span = hit.element.arg_spans.get(hit.field)
        if not isinstance(value, str) or span is None:
            return None
        if field.kind == "label":
            return value, "label", span
        if names.takes_name(hit.element.kind, hit.field) and names.is_name(value):
            return value, "name", span
        return None
    if analysis.kind == LD and hit is None:
        word = word_at(text, col)
        if word and _known(analysis, word[2]):
            return word[2], "name", Span.at(line, word[0], word[1])
    return None


def _known(analysis, word: str) -> bool:
    program = analysis.program
    return word in analysis.index.uses or word in program.pins or word in program.var_sizes


def label_places(analysis, label: str) -> tuple[list[Span], list[Span]]:
    """(definitions: LABEL/SUBPROG, uses: GOTO/GOSUB/ENDSUB) of a label."""
    definitions: list[Span] = []
    uses: list[Span] = []
    for _, element in analysis.program.elements():
        if element.kind in LABEL_KINDS and element.args.get("label") == label:
            span = element.arg_spans.get("label") or element.span
            if span is None:
                continue
            (definitions if element.kind in ("LABEL", "SUBPROG") else uses).append(span)
    return definitions, uses


def pin_span(analysis, name: str) -> Span | None:
    assignment = analysis.program.pins.get(name)
    return assignment.span if assignment is not None else None


def other_rows(analysis, name: str) -> list[Span]:
    """Occurrences of a name in the I/O table, VAR LIST and DETAILS (text form)."""
    if analysis.kind != LADDER:
        span = pin_span(analysis, name)
        return [span] if span is not None else []
    found = []
    import re

    pattern = re.compile(rf"(?<![\w$#@.]){re.escape(name)}(?![\w$#@.])")
    for title in (IO, VARS, DETAILS):
        bounds = analysis.locator.section_range(title)
        if bounds is None:
            continue
        for number in range(bounds[0] + 1, bounds[1] + 1):
            for match in pattern.finditer(analysis.line(number)):
                found.append(Span.at(number, match.start(), match.end()))
    return found


def _location(analysis, span: Span) -> types.Location:
    return types.Location(uri=analysis.uri, range=analysis.positions.range(span))


def register(server) -> None:
    def target(ls, params):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None, None
        line, col = analysis.positions.from_client(params.position)
        return analysis, name_at(analysis, line, col)

    @server.on(types.TEXT_DOCUMENT_DEFINITION)
    def definition(ls, params: types.DefinitionParams):
        analysis, found = target(ls, params)
        if not found:
            return None
        name, what, _ = found
        if what == "label":
            definitions, _ = label_places(analysis, name)
            return [_location(analysis, s) for s in definitions] or None
        uses = names.uses_of(analysis.index, name)
        spans = [u.span for u in uses.writes if u.span is not None]
        if not spans:
            pin = pin_span(analysis, name)
            spans = [pin] if pin is not None else [u.span for u in uses.uses[:1] if u.span is not None]
        return [_location(analysis, s) for s in spans] or None

    @server.on(types.TEXT_DOCUMENT_REFERENCES)
    def references(ls, params: types.ReferenceParams):
        analysis, found = target(ls, params)
        if not found:
            return None
        name, what, _ = found
        if what == "label":
            definitions, uses = label_places(analysis, name)
            spans = (definitions if params.context.include_declaration else []) + uses
        else:
            spans = [u.span for u in names.uses_of(analysis.index, name).uses if u.span is not None]
            if params.context.include_declaration:
                spans += other_rows(analysis, name)
        return [_location(analysis, s) for s in sorted(set(spans))]

    @server.on(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
    def highlight(ls, params: types.DocumentHighlightParams):
        analysis, found = target(ls, params)
        if not found:
            return None
        name, what, _ = found
        result = []
        if what == "label":
            definitions, uses = label_places(analysis, name)
            for span in definitions:
                result.append(types.DocumentHighlight(range=analysis.positions.range(span),
                                                      kind=types.DocumentHighlightKind.Write))
            for span in uses:
                result.append(types.DocumentHighlight(range=analysis.positions.range(span),
                                                      kind=types.DocumentHighlightKind.Read))
            return result
        for use in names.uses_of(analysis.index, name).uses:
            if use.span is None:
                continue
            kind = types.DocumentHighlightKind.Write if use.writes else types.DocumentHighlightKind.Read
            result.append(types.DocumentHighlight(range=analysis.positions.range(use.span), kind=kind))
        for span in other_rows(analysis, name):
            result.append(types.DocumentHighlight(range=analysis.positions.range(span),
                                                  kind=types.DocumentHighlightKind.Text))
        return result

    @server.on(types.TEXT_DOCUMENT_PREPARE_RENAME)
    def prepare_rename(ls, params: types.PrepareRenameParams):
        analysis, found = target(ls, params)
        if not found:
            return None
        if analysis.has_errors:
            raise UserError("fix the errors in this file before renaming")
        name, _, span = found
        return types.PrepareRenamePlaceholder(range=analysis.positions.range(span), placeholder=name)

    @server.on(types.TEXT_DOCUMENT_RENAME)
    def rename(ls, params: types.RenameParams):
        analysis, found = target(ls, params)
        if not found:
            return None
        if analysis.has_errors:
            raise UserError("fix the errors in this file before renaming")
        name = found[0]
        return workspace_edit(ls, analysis, *rename_edits(analysis, name, params.new_name))


def rename_edits(analysis, old: str, new: str):
    try:
        return edits.rename(analysis.program, analysis.locator, analysis.text, old, new, analysis.kind)
    except edits.EditError as problem:
        raise UserError(str(problem)) from problem


def newline(analysis) -> str:
    return "\r\n" if "\r\n" in analysis.text[:4096] else "\n"


def text_edits(analysis, line_edits, column_edits) -> list[types.TextEdit]:
    """LSP edits from ide.edits' line and column edits."""
    nl = newline(analysis)
    result = []
    positions = analysis.positions
    for edit in line_edits:
        body = "".join(line + nl for line in edit.lines)
        result.append(types.TextEdit(range=positions.line_range(edit.first, edit.last), new_text=body))
    for edit in column_edits:
        result.append(types.TextEdit(range=positions.range(Span.at(edit.line, edit.col, edit.end_col)),
                                     new_text=edit.text))
    return result


def workspace_edit(ls, analysis, line_edits, column_edits) -> types.WorkspaceEdit:
    changes = text_edits(analysis, line_edits, column_edits)
    if ls.client_supports("workspace", "workspace_edit", "document_changes"):
        return types.WorkspaceEdit(document_changes=[types.TextDocumentEdit(
            text_document=types.OptionalVersionedTextDocumentIdentifier(uri=analysis.uri, version=analysis.version),
            edits=changes)])
    return types.WorkspaceEdit(changes={analysis.uri: changes})
