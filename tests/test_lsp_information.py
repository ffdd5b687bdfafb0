"""An info diagnostic (LD133) reaches the editor as Information, shown
faintly, not as a warning."""

from __future__ import annotations

from pathlib import Path

import pytest
from lsprotocol import types
from test_lsp_support import Doc, lsp_fixture, new_uri

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


async def test_an_info_is_information(client):
    doc = Doc(client, new_uri(), (Path(__file__).parent / "diagnostics" / "LD133.ladder").read_text(encoding="utf-8"))
    found = await doc.diagnostics()
    assert [(d.code, d.severity) for d in found] == [("LD133", types.DiagnosticSeverity.Information)]
    assert doc.lines[found[0].range.start.line][found[0].range.start.character:].startswith("Rready")
