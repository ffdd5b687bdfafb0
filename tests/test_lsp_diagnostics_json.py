"""The server writes each published diagnostic's JSON itself (lsp/diagnostics.py
`encoded`, for speed): it says what lsprotocol's own converter says of the
same LSP diagnostic, places in the client's code units included."""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest
from lsprotocol import converters, types
from pygls.workspace import PositionCodec

from lang.diagnostics import ERROR, INFO, WARNING, Diagnostic, Related
from lang.model import Span
from lsp.diagnostics import encoded
from lsp.positions import Positions

LINES = ["    ||       Xa        Yb      ||", '0001||--] [--{"é😀 ok"}--( )--||', "plain line", ""]
URI = "file:///tmp/doc%20one.ladder"
SEVERITIES = {ERROR: types.DiagnosticSeverity.Error, WARNING: types.DiagnosticSeverity.Warning,
              INFO: types.DiagnosticSeverity.Information}

DIAGNOSTICS = [
    Diagnostic("LD102", ERROR, "coil 'Yb' on an input", Span(0, 22, 0, 24)),
    Diagnostic("LD131", WARNING, 'a "quoted" \\ name, é and 😀', Span(1, 20, 1, 30)),
    Diagnostic("LD133", INFO, "read before written", Span(1, 4, 2, 3),
               (Related(Span(1, 27, 1, 30), "written here"), Related(Span(2, 0, 2, 5), "and 'here'"))),
    Diagnostic("LD001", ERROR, "no place", None),
    Diagnostic("LD002", WARNING, "past the end", Span(7, 0, 7, 2), (Related(Span(3, 0, 3, 0), "empty line"),)),
]


def expected(positions: Positions, diagnostic: Diagnostic, related: bool) -> dict:
    """The LSP diagnostic built with lsprotocol's types, written by its converter."""
    place = positions.range
    places = [types.DiagnosticRelatedInformation(location=types.Location(uri=URI, range=place(r.span)),
                                                 message=r.message) for r in diagnostic.related] if related else []
    return converters.get_converter().unstructure(types.Diagnostic(
        range=place(diagnostic.span), message=diagnostic.message, severity=SEVERITIES[diagnostic.severity],
        code=diagnostic.code, source="ladder", related_information=places or None))


@pytest.mark.parametrize("encoding", ["utf-16", "utf-8", "utf-32"])
@pytest.mark.parametrize("related", [True, False])
def test_a_diagnostic_written_directly_is_what_the_converter_writes(encoding, related):
    positions = Positions(LINES, PositionCodec(encoding), ascii_text=False)
    analysis = SimpleNamespace(positions=positions)
    server = SimpleNamespace(client_supports=lambda *capability: related)
    for diagnostic in DIAGNOSTICS:
        assert json.loads(encoded(server, analysis, diagnostic, json.dumps(URI))) == \
            expected(positions, diagnostic, related)
    # the non-ASCII line's columns are in code units: é😀 are 3 UTF-16 units, 6 UTF-8 bytes
    written = json.loads(encoded(server, analysis, DIAGNOSTICS[1], json.dumps(URI)))
    assert written["range"]["end"]["character"] == {"utf-16": 31, "utf-8": 34, "utf-32": 30}[encoding]
