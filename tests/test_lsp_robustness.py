"""The server survives anything: bytes that are not UTF-8, a 10 MB document,
positions past the end, edits during a real-time simulation, a malformed
request, a notification for a document never opened, and a bug inside one
feature (answered with an error and logged; the other features go on)."""

from __future__ import annotations

import asyncio
import json

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException
from test_lsp_support import Doc, example_text, hover_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
# a bug injected into folding and into one command, as if the code had one
client = lsp_fixture(env={"LADDER_LSP_FAULTS": "textDocument/foldingRange,ladder.build"})

FAR = types.Position(line=10**6, character=10**6)


async def alive(client) -> None:
    """A request that must be answered normally."""
    doc = Doc(client, new_uri(), example_text())
    assert await doc.diagnostics() == []
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=td(doc.uri)))
    assert symbols


def raw(client, body: bytes) -> None:
    client._server.stdin.write(b"Content-Length: %d\r\n\r\n" % len(body) + body)


async def test_invalid_utf8_on_the_wire(client):
    body = json.dumps({"jsonrpc": "2.0", "id": 999001, "method": "textDocument/hover",
                       "params": {"textDocument": {"uri": "file:///x.ladder"},
                                  "position": {"line": 0, "character": 0}}}).encode()
    raw(client, body.replace(b"x.ladder", b"\xff\xfe.ladder"))
    raw(client, b"{not json at all")
    raw(client, json.dumps({"jsonrpc": "2.0", "id": 999002, "method": "textDocument/hover",
                            "params": {"textDocument": {}}}).encode())  # no position
    await asyncio.sleep(0.2)
    await alive(client)


async def test_text_that_is_not_valid_unicode(client):
    # lone surrogates are valid JSON escapes but no valid UTF-8
    text = example_text().replace("Conveyor:", "Conv\udcffyor:").replace("Yhorn", "Yh\ud800rn")
    doc = Doc(client, new_uri(), text)
    await doc.diagnostics()
    for position in (doc.find("Conv"), doc.find("Yh")):
        await client.text_document_completion_async(types.CompletionParams(text_document=td(doc.uri),
                                                                           position=position))
    await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=td(doc.uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)))
    await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=td(doc.uri)))
    await alive(client)


async def test_a_ten_megabyte_document(client):
    rung = example_text().split("LADDER DIAGRAM:\n")[1].split("   4||")[0]
    text = example_text().replace(rung, rung * (10_000_000 // len(rung) + 1), 1)
    assert len(text) > 10_000_000
    doc = Doc(client, new_uri(), text)
    loop = asyncio.get_running_loop()
    start = loop.time()
    found = await doc.diagnostics(timeout=30)
    assert [d.code for d in found] == ["lsp-too-large"] and "too large" in found[0].message
    result = await client.text_document_definition_async(types.DefinitionParams(
        text_document=td(doc.uri), position=doc.find("Rrun", 2)))
    assert result is None  # not analysed
    doc.change(5, 0, 5, 0, "x")
    await doc.diagnostics(timeout=30)
    assert loop.time() - start < 20
    doc.close()
    await alive(client)


async def test_positions_past_the_end(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    ident = td(doc.uri)
    for position in (FAR, types.Position(line=3, character=10**6), types.Position(line=10**6, character=0)):
        await client.text_document_completion_async(types.CompletionParams(text_document=ident, position=position))
        await client.text_document_definition_async(types.DefinitionParams(text_document=ident, position=position))
        await client.text_document_references_async(types.ReferenceParams(
            text_document=ident, position=position, context=types.ReferenceContext(include_declaration=True)))
        await client.text_document_document_highlight_async(
            types.DocumentHighlightParams(text_document=ident, position=position))
        await client.text_document_code_action_async(types.CodeActionParams(
            text_document=ident, range=types.Range(start=position, end=FAR),
            context=types.CodeActionContext(diagnostics=[])))
        await client.text_document_inlay_hint_async(types.InlayHintParams(
            text_document=ident, range=types.Range(start=position, end=FAR)))
        await client.text_document_semantic_tokens_range_async(types.SemanticTokensRangeParams(
            text_document=ident, range=types.Range(start=position, end=FAR)))
    # an edit whose range lies past the end of the document
    doc.client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri=doc.uri, version=50),
        content_changes=[types.TextDocumentContentChangePartial(range=types.Range(start=FAR, end=FAR), text="x")]))
    # a change to a document that was never opened
    doc.client.text_document_did_change(types.DidChangeTextDocumentParams(
        text_document=types.VersionedTextDocumentIdentifier(uri="file:///never/opened.ladder", version=2),
        content_changes=[types.TextDocumentContentChangeWholeDocument(text="x")]))
    await alive(client)


async def test_requests_for_documents_never_opened(client):
    ident = td("file:///no/such/file.ladder")
    assert await client.text_document_hover_async(types.HoverParams(
        text_document=ident, position=types.Position(line=0, character=0))) is None
    assert not await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=ident))
    with pytest.raises(JsonRpcException):
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="ladder.sim.start", arguments=[ident.uri]))
    with pytest.raises(JsonRpcException):
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="ladder.sim.step", arguments=[]))
    await alive(client)


async def test_edits_during_a_realtime_simulation(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.start", arguments=[doc.uri]))
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.runRealtime", arguments=[doc.uri, True]))
    until = asyncio.ensure_future(client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.runUntil", arguments=[doc.uri, "Cruns >= 100", 5000])))
    line = doc.find("0004||").line
    for n in range(40):  # type, break, repair, add and remove lines, as fast as possible
        col = (n * 7) % 60 + 6
        doc.change(line, col, line, col + 1, "|" if n % 3 == 0 else "-")
        if n % 5 == 0:
            doc.change(line + 1, 0, line + 1, 0, "    ||\n")
        if n % 10 == 0:
            await asyncio.sleep(0.05)
    doc.replace_all(example_text())
    result = await asyncio.wait_for(until, 30)
    assert result["reached"] is False
    state = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.step", arguments=[doc.uri]))
    assert state["running"] is True
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.stop", arguments=[doc.uri]))
    assert await doc.diagnostics() == []
    await alive(client)


async def test_a_bug_in_one_feature(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    for _ in range(2):
        with pytest.raises(Exception) as problem:
            await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=td(doc.uri)))
        assert "injected fault" in str(problem.value)
    with pytest.raises(Exception) as problem:
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="ladder.build", arguments=[doc.uri]))
    assert "injected fault" in str(problem.value)
    # logged with its traceback
    assert any("injected fault" in m.message and "Traceback" in m.message for m in client.log_messages)
    # everything else works
    assert "digital input" in hover_text(await client.text_document_hover_async(
        types.HoverParams(text_document=td(doc.uri), position=doc.find("Xstart"))))
    items = await client.text_document_completion_async(types.CompletionParams(
        text_document=td(doc.uri), position=doc.find("Yhorn")))
    assert items.items
    await alive(client)
