"""Completion (ide.completion) as LSP's: each item's main edit is its
`textEdit`, its edits of other lines its `additionalTextEdits`; snippets
when the client takes them."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types

from ide.completion import Item, Kind, complete
from ide.edits import RangeEdit

from .positions import Positions

if TYPE_CHECKING:
    from .server import LadderServer

KINDS = {Kind.NAME: types.CompletionItemKind.Variable, Kind.PART: types.CompletionItemKind.Module,
         Kind.PIN: types.CompletionItemKind.Value, Kind.DRAWING: types.CompletionItemKind.Snippet,
         Kind.INSTRUCTION: types.CompletionItemKind.Keyword}


def register(server: LadderServer) -> None:
    @server.on(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["'"]))
    def completion(ls: LadderServer, params: types.CompletionParams) -> types.CompletionList | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        line, col = analysis.positions.from_client(params.position)
        snippets = ls.client_supports("text_document", "completion", "completion_item", "snippet_support")
        found = complete(analysis, line, col, snippets)
        if found is None:
            return None
        positions = analysis.positions
        return types.CompletionList(is_incomplete=found.incomplete, items=[_item(positions, i) for i in found.items])


def _edit(positions: Positions, edit: RangeEdit) -> types.TextEdit:
    return types.TextEdit(range=positions.range(edit.span), new_text=edit.text)


def _item(positions: Positions, item: Item) -> types.CompletionItem:
    return types.CompletionItem(
        label=item.label, kind=KINDS[item.kind], detail=item.detail, documentation=item.documentation,
        sort_text=item.sort, filter_text=item.filter,
        insert_text_format=types.InsertTextFormat.Snippet if item.snippet else None,
        text_edit=_edit(positions, item.edit),
        additional_text_edits=[_edit(positions, e) for e in item.more] or None)
