"""Formatting (ide.formatting) as LSP text edits, for the text form only:
`.ld` files are LDmicro's own format and are left as they are."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types

from ide.formatting import format_edits

from .documents import LADDER

if TYPE_CHECKING:
    from .server import LadderServer


def register(server: LadderServer) -> None:
    @server.on(types.TEXT_DOCUMENT_FORMATTING)
    def formatting(ls: LadderServer, params: types.DocumentFormattingParams) -> list[types.TextEdit] | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None or analysis.kind != LADDER:
            return None
        found = format_edits(analysis.text, analysis.program, analysis.problems)
        if found is None:
            ls.log("not formatted: the file has errors", types.MessageType.Info)
            return []
        positions = analysis.positions
        return [types.TextEdit(range=positions.range(edit.span), new_text=edit.text) for edit in found]
