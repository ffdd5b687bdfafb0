"""Hover (ide.hover) as LSP's: Markdown, or plain text for a client that
takes only that; while a simulation of the document runs, names show their
values."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lsprotocol import types

from ide.hover import hover_at

if TYPE_CHECKING:
    from .server import LadderServer


def register(server: LadderServer) -> None:
    @server.on(types.TEXT_DOCUMENT_HOVER)
    def hover(ls: LadderServer, params: types.HoverParams) -> types.Hover | None:
        uri = params.text_document.uri
        analysis = ls.documents.analysis(uri)
        if analysis is None:
            return None
        line, col = analysis.positions.from_client(params.position)
        sims = ls.simulations
        found = hover_at(analysis, line, col, lambda name: sims.value_of(uri, name) if sims is not None else None)
        if found is None:
            return None
        markdown = _markdown(ls)
        return types.Hover(
            contents=types.MarkupContent(kind=types.MarkupKind.Markdown if markdown else types.MarkupKind.PlainText,
                                         value=found.markdown if markdown else _plain(found.markdown)),
            range=analysis.positions.range(found.span) if found.span is not None else None)


def _markdown(ls: LadderServer) -> bool:
    capabilities: types.ClientCapabilities | None = getattr(ls.protocol, "client_capabilities", None)
    document = capabilities.text_document if capabilities is not None else None
    hover = document.hover if document is not None else None
    formats = hover.content_format if hover is not None else None
    return not formats or types.MarkupKind.Markdown in formats


def _plain(text: str) -> str:
    return text.replace("**", "").replace("`", "")
