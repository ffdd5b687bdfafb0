"""Diagnostics as you type: the reader's and the checks' problems, with the
codes `ladder check` gives, a link to each code's documentation and the
related places a check names. Published at once when a document opens and
`ladder.diagnosticsDelayMs` after the last change while typing (0: as soon as
the messages that have arrived are read, so that of edits queued up only the
last one is checked)."""

from __future__ import annotations

import asyncio
import json
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from lsprotocol import types

from ide.diagnostics import shown
from lang.diagnostics import ERROR, INFO, Diagnostic
from lang.model import Span

from .documents import Analysis
from .positions import Positions
from .protocol import Encoded

if TYPE_CHECKING:
    from .server import LadderServer

SOURCE = "ladder"


class Publisher:
    def __init__(self, server: LadderServer):
        self.server = server
        self.pending: dict[str, asyncio.Handle] = {}
        self.published: dict[str, int | None] = {}
        # analysis + publication after the last change: the adaptive delay's measure (an
        # open reads and checks the whole document, an edit only what it changed)
        self.last_duration_ms = 0.0
        self.extra: dict[str, list[Diagnostic]] = {}  # the compiler's, until the next change
        self.encoded: dict[str, dict[Diagnostic, str]] = {}  # uri -> the JSON of each diagnostic published
        # other features' diagnostics of a version, published with these (lsp/verify.py's results)
        self.sources: list[Callable[[Analysis], list[types.Diagnostic]]] = []

    def set_extra(self, uri: str, found: list[Diagnostic]) -> None:
        self.extra[uri] = list(found)
        self.publish(uri)

    def schedule(self, uri: str) -> None:
        delay = self.server.settings.delay_ms(self.last_duration_ms)
        self.cancel(uri)
        loop = asyncio.get_event_loop()
        if delay <= 0:
            # once the messages that have arrived are read (lsp/transport.py): of edits that
            # queued up while the server was busy, only the last one is checked and published
            self.pending[uri] = loop.call_soon(self._run, uri)
            return
        self.pending[uri] = loop.call_later(delay / 1000, self._run, uri)

    def _run(self, uri: str) -> None:
        self.pending.pop(uri, None)
        try:
            with self.server.idle.reading():
                self.publish(uri, after_change=True)
        except Exception as problem:
            self.server._failure("publishDiagnostics", problem)

    def cancel(self, uri: str) -> None:
        handle = self.pending.pop(uri, None)
        if handle is not None:
            handle.cancel()

    def publish(self, uri: str, after_change: bool = False) -> None:
        start = time.perf_counter()
        analysis = self.server.documents.analysis(uri, include_too_large=True)
        if analysis is None:
            if uri in self.published:
                self.clear(uri)
            return
        # each diagnostic's JSON is kept for the next publication: an edit changes a few of them,
        # a big document may have thousands. Positions on ASCII lines are the same for the client,
        # so a diagnostic whose places are all on such lines is encoded once (a document whose VAR
        # LIST has one accented comment keeps its thousands of diagnostics in the drawing encoded)
        positions = analysis.positions
        known = self.encoded.get(uri, {})
        uri_json = json.dumps(uri)
        kept: dict[Diagnostic, str] = {}
        texts = []
        for diagnostic in shown(analysis.diagnostics, self.extra.get(uri, [])):
            plain = positions.ascii or (positions.same_for_client(diagnostic.span) and all(
                positions.same_for_client(related.span) for related in diagnostic.related))
            text = known.get(diagnostic) if plain else None
            if text is None:
                text = encoded(self.server, analysis, diagnostic, uri_json)
            if plain:
                kept[diagnostic] = text
            texts.append(text)
        self.encoded[uri] = kept
        texts += [json.dumps(self.server.protocol._converter.unstructure(d), separators=(",", ":"))
                  for source in self.sources for d in source(analysis)]
        self.server.notify(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS, Encoded(
            f'{{"uri":{json.dumps(uri)},"version":{json.dumps(analysis.version)},'
            f'"diagnostics":[{",".join(texts)}]}}'))
        self.published[uri] = analysis.version
        if after_change:
            self.last_duration_ms = (time.perf_counter() - start) * 1000

    def clear(self, uri: str) -> None:
        self.cancel(uri)
        self.published.pop(uri, None)
        self.encoded.pop(uri, None)
        self.server.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


_SEVERITIES = {ERROR: types.DiagnosticSeverity.Error, INFO: types.DiagnosticSeverity.Information}


def encoded(server: LadderServer, analysis: Analysis, diagnostic: Diagnostic, uri_json: str) -> str:
    """The diagnostic as LSP's JSON (a `types.Diagnostic` as the protocol's
    converter writes it), written directly: a line added above a thousand
    diagnostics moves them all, and each is written again, a fifth of the time
    the converter takes. `uri_json`: the document's URI as JSON."""
    positions = analysis.positions
    severity = _SEVERITIES.get(diagnostic.severity, types.DiagnosticSeverity.Warning).value
    text = (f'{{"range":{_range(positions, diagnostic.span)},"message":{json.dumps(diagnostic.message)},'
            f'"severity":{severity},"code":{json.dumps(diagnostic.code)},"source":"{SOURCE}"')
    places = [f'{{"location":{{"uri":{uri_json},"range":{_range(positions, r.span)}}},'
              f'"message":{json.dumps(r.message)}}}' for r in diagnostic.related if r.span is not None] \
        if diagnostic.related and server.client_supports("text_document", "publish_diagnostics",
                                                         "related_information") else []
    return text + (f',"relatedInformation":[{",".join(places)}]}}' if places else "}")


def _range(positions: Positions, span: Span | None) -> str:
    line, character, end_line, end_character = positions.place(span)
    return (f'{{"start":{{"line":{line},"character":{character}}},'
            f'"end":{{"line":{end_line},"character":{end_character}}}}}')


def register(server: LadderServer) -> None:
    publisher = server.diagnostics = Publisher(server)

    def opened(ls: LadderServer, uri: str | None) -> None:
        assert uri is not None  # a document event
        publisher.cancel(uri)
        with ls.idle.reading():
            publisher.publish(uri)

    def changed(ls: LadderServer, uri: str | None) -> None:
        assert uri is not None
        publisher.extra.pop(uri, None)
        publisher.schedule(uri)

    def closed(ls: LadderServer, uri: str | None) -> None:
        assert uri is not None
        publisher.extra.pop(uri, None)
        publisher.clear(uri)

    def configured(ls: LadderServer, _: str | None) -> None:
        ls.documents.reconfigure()
        for uri in list(publisher.published):
            publisher.schedule(uri)

    server.subscribe("opened", opened)
    server.subscribe("changed", changed)
    server.subscribe("closed", closed)
    server.subscribe("configured", configured)
