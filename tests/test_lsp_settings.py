"""End to end: the `ladder` settings, pulled after `initialized` and pushed
with didChangeConfiguration; diagnostics debounced while typing."""

from __future__ import annotations

import asyncio

import pytest
from lsprotocol import types
from test_lsp_support import Doc, example_text, lsp_fixture, new_uri

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture(settings={"diagnosticsDelayMs": 400})


async def test_diagnostics_are_debounced(client):
    doc = Doc(client, new_uri(), example_text())
    assert await doc.diagnostics() == []  # at once when opened
    published = []
    original = client.protocol.fm._features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS]

    def spy(params):
        published.append((params.version, asyncio.get_running_loop().time()))
        original(params)

    client.protocol.fm._features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = spy
    try:
        line = doc.find("0004||").line
        for n in range(5):
            doc.change(line, 10 + n, line, 11 + n, "-")
            await asyncio.sleep(0.05)
        last_change = asyncio.get_running_loop().time()
        await doc.diagnostics()
        mine = [p for p in published if p[0] and p[0] > 1]
        assert [v for v, _ in mine] == [doc.version]  # one publication, for the last version
        assert mine[0][1] - last_change >= 0.3
    finally:
        client.protocol.fm._features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = original


async def test_settings_pushed_by_the_client(client):
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"ladder": {"diagnosticsDelayMs": 0}}))
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    line = doc.find("0004||").line
    loop = asyncio.get_running_loop()
    start = loop.time()
    doc.change(line, 10, line, 11, "-")
    await doc.diagnostics()
    assert loop.time() - start < 0.35
    # a bad value is refused with a warning, the others still apply
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"ladder": {"diagnosticsDelayMs": "soon", "encoding": "no-such-codec"}}))
    for _ in range(100):
        if any("diagnosticsDelayMs" in m.message for m in client.log_messages):
            break
        await asyncio.sleep(0.02)
    messages = [m.message for m in client.log_messages]
    assert any("diagnosticsDelayMs" in m for m in messages) and any("no-such-codec" in m for m in messages)
    doc.change(line, 10, line, 11, "-")
    assert await doc.diagnostics() == []


async def test_severities_from_the_project_and_the_editor(client, tmp_path):
    """`[tool.ladder.diagnostics]` of the nearest pyproject.toml, with the
    editor's `ladder.diagnostics` on top."""
    (tmp_path / "pyproject.toml").write_text('[tool.ladder.diagnostics]\nLD130 = "error"\n', encoding="utf-8")
    uri = (tmp_path / "p.ladder").as_uri()
    doc = Doc(client, uri, example_text().replace("Xstop", "Rnever", 1))  # a relay never written: LD130
    found = await doc.diagnostics()
    assert [(d.code, d.severity) for d in found if d.code == "LD130"] == [("LD130", types.DiagnosticSeverity.Error)]
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"ladder": {"diagnostics": {"LD130": "off"}}}))
    for _ in range(100):
        await asyncio.sleep(0.05)
        if "LD130" not in [d.code for d in client.diagnostics.get(uri, [])]:
            break
    assert "LD130" not in [d.code for d in client.diagnostics[uri]]
    client.workspace_did_change_configuration(types.DidChangeConfigurationParams(
        settings={"ladder": {"diagnostics": {}}}))

