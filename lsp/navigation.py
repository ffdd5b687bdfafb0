"""Names across the program (ide.navigation) as LSP's: definition,
references, document highlight, rename; and the workspace edits other
features answer with (ide.edits' line and column edits as LSP text edits)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from lsprotocol import types

from ide import navigation
from ide.document import newline
from ide.edits import EditError, LineEdit, TextEdit
from ide.navigation import Access, Occurrence
from lang.model import Span

from .documents import Analysis
from .protocol import UserError

if TYPE_CHECKING:
    from .server import LadderServer

HIGHLIGHTS = {Access.WRITE: types.DocumentHighlightKind.Write, Access.READ: types.DocumentHighlightKind.Read,
              Access.TEXT: types.DocumentHighlightKind.Text}
Positioned = (types.DefinitionParams | types.ReferenceParams | types.DocumentHighlightParams
              | types.PrepareRenameParams | types.RenameParams)


def _locations(analysis: Analysis, spans: Iterable[Span]) -> list[types.Location]:
    return [types.Location(uri=analysis.uri, range=analysis.positions.range(span)) for span in spans]


def register(server: LadderServer) -> None:
    def target(ls: LadderServer, params: Positioned) -> tuple[Analysis, Occurrence] | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        line, col = analysis.positions.from_client(params.position)
        found = navigation.name_at(analysis, line, col)
        return (analysis, found) if found is not None else None

    @server.on(types.TEXT_DOCUMENT_DEFINITION)
    def definition(ls: LadderServer, params: types.DefinitionParams) -> list[types.Location] | None:
        found = target(ls, params)
        if found is None:
            return None
        return _locations(found[0], navigation.definition(*found)) or None

    @server.on(types.TEXT_DOCUMENT_REFERENCES)
    def references(ls: LadderServer, params: types.ReferenceParams) -> list[types.Location] | None:
        found = target(ls, params)
        if found is None:
            return None
        return _locations(found[0], navigation.references(*found, params.context.include_declaration))

    @server.on(types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT)
    def highlight(ls: LadderServer, params: types.DocumentHighlightParams) -> list[types.DocumentHighlight] | None:
        found = target(ls, params)
        if found is None:
            return None
        positions = found[0].positions
        return [types.DocumentHighlight(range=positions.range(h.span), kind=HIGHLIGHTS[h.access])
                for h in navigation.highlights(*found)]

    @server.on(types.TEXT_DOCUMENT_PREPARE_RENAME)
    def prepare_rename(ls: LadderServer, params: types.PrepareRenameParams) -> types.PrepareRenamePlaceholder | None:
        found = target(ls, params)
        if found is None:
            return None
        analysis, name = found
        try:
            navigation.renamable(analysis)
        except EditError as problem:
            raise UserError(str(problem)) from problem
        return types.PrepareRenamePlaceholder(range=analysis.positions.range(name.span), placeholder=name.name)

    @server.on(types.TEXT_DOCUMENT_RENAME)
    def rename(ls: LadderServer, params: types.RenameParams) -> types.WorkspaceEdit | None:
        found = target(ls, params)
        if found is None:
            return None
        analysis, name = found
        try:
            changes = navigation.rename(analysis, name.name, params.new_name)
        except EditError as problem:
            raise UserError(str(problem)) from problem
        return workspace_edit(ls, analysis, *changes)


def text_edits(analysis: Analysis, line_edits: Iterable[LineEdit], column_edits: Iterable[TextEdit]
               ) -> list[types.TextEdit]:
    """LSP edits from ide.edits' line and column edits."""
    nl = newline(analysis.text)
    result = []
    positions = analysis.positions
    for edit in line_edits:
        body = "".join(line + nl for line in edit.lines)
        result.append(types.TextEdit(range=positions.line_range(edit.first, edit.last), new_text=body))
    for column_edit in column_edits:
        result.append(types.TextEdit(range=positions.range(Span.at(column_edit.line, column_edit.col,
                                                                   column_edit.end_col)),
                                     new_text=column_edit.text))
    return result


def workspace_edit(ls: LadderServer, analysis: Analysis, line_edits: Iterable[LineEdit],
                   column_edits: Iterable[TextEdit]) -> types.WorkspaceEdit:
    changes = text_edits(analysis, line_edits, column_edits)
    if ls.client_supports("workspace", "workspace_edit", "document_changes"):
        return types.WorkspaceEdit(document_changes=[types.TextDocumentEdit(
            text_document=types.OptionalVersionedTextDocumentIdentifier(uri=analysis.uri, version=analysis.version),
            edits=changes)])
    return types.WorkspaceEdit(changes={analysis.uri: changes})
