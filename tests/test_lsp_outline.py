"""End to end: document symbols, folding ranges, semantic tokens."""

from __future__ import annotations

import pytest
from lsprotocol import types
from test_lsp_incremental import big_text
from test_lsp_support import Doc, example_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


async def test_document_symbols(client):
    doc = Doc(client, new_uri(), example_text())
    symbols = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=td(doc.uri)))
    names = [s.name for s in symbols]
    assert "LADDER DIAGRAM" in names and "I/O ASSIGNMENT" in names
    diagram = next(s for s in symbols if s.name == "LADDER DIAGRAM")
    rungs = diagram.children
    assert [r.name for r in rungs][:2] == ["Rung 1: ; Conveyor: start/stop with seal-in. The horn", "Rung 2"]
    assert rungs[1].detail == "Rrun := (Xstart | Rrun) & !Xstop"
    assert [c.name for c in rungs[2].children] == ["Twarn", "Ymotor", "Cruns"]
    assert rungs[1].range.start.line == doc.find("Xstart").line


async def test_folding_per_rung_and_section(client):
    doc = Doc(client, new_uri(), example_text())
    ranges = await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=td(doc.uri)))
    starts = {(r.start_line, r.end_line) for r in ranges}
    rung2 = doc.find("Xstart").line
    assert (rung2, doc.find("    |+-------] [------+").line) in starts
    comment = next(r for r in ranges if r.kind == types.FoldingRangeKind.Comment)
    assert doc.lines[comment.start_line].strip().startswith("|| ;")


def decode(data: list[int]) -> list[tuple[int, int, int, int, int]]:
    out, line, col = [], 0, 0
    for i in range(0, len(data), 5):
        dl, dc, length, kind, mods = data[i:i + 5]
        line += dl
        col = dc if dl else col + dc
        out.append((line, col, length, kind, mods))
    return out


async def test_semantic_tokens(client):
    doc = Doc(client, new_uri(), example_text())
    result = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=td(doc.uri)))
    # the legend the server announced
    legend = client.init_result.capabilities.semantic_tokens_provider.legend
    tokens = decode(result.data)
    text = {(doc.lines[ln][c:c + n], legend.token_types[k]) for ln, c, n, k, _ in tokens}
    assert ("Xstart", "parameter") in text  # an input
    assert ("Ymotor", "property") in text  # an output
    assert ("Rrun", "variable") in text  # a relay
    assert ("Twarn", "function") in text  # a timer
    assert ("] [", "keyword") in text and ("( )", "keyword") in text
    assert ("2 s", "number") in text and ("[TON", "keyword") in text
    assert ("0002", "number") in text
    assert ("LADDER DIAGRAM:", "namespace") in text
    written = [(doc.lines[ln][c:c + n], m) for ln, c, n, k, m in tokens if doc.lines[ln][c:c + n] == "Rrun"]
    assert sorted(m for _, m in written)[-1] != 0  # the coil writes it: a modifier
    # ordered, no overlaps
    positions = [(ln, c, c + n) for ln, c, n, _, _ in tokens]
    for a, b in zip(positions, positions[1:]):
        assert (a[0], a[2]) <= (b[0], b[1])
    ranged = await client.text_document_semantic_tokens_range_async(types.SemanticTokensRangeParams(
        text_document=td(doc.uri), range=types.Range(start=types.Position(line=0, character=0),
                                                      end=types.Position(line=12, character=0))))
    assert 0 < len(ranged.data) < len(result.data)
    # the full answer is assembled from each rung's kept encoding: it equals encoding everything at once
    whole = await client.text_document_semantic_tokens_range_async(types.SemanticTokensRangeParams(
        text_document=td(doc.uri), range=types.Range(start=types.Position(line=0, character=0),
                                                      end=types.Position(line=len(doc.lines), character=0))))
    assert whole.data == result.data
    # also where columns differ in the client's units (a comment with characters beyond ASCII)
    wide = Doc(client, new_uri(), example_text().replace("Conveyor: start/stop", "Förderband 🚚 start"))
    full = await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=td(wide.uri)))
    whole = await client.text_document_semantic_tokens_range_async(types.SemanticTokensRangeParams(
        text_document=td(wide.uri), range=types.Range(start=types.Position(line=0, character=0),
                                                       end=types.Position(line=len(wide.lines), character=0))))
    assert whole.data == full.data


async def test_semantic_tokens_delta(client):
    """After an edit the client asks for the change since the answer it has:
    applied to that answer, it is the new version's whole answer."""
    doc = Doc(client, new_uri(), example_text())
    ident = td(doc.uri)
    first = await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=ident))
    at = doc.find("Xstart")
    doc.change(at.line, at.character + 1, at.line, at.character + 1, "q")
    delta = await client.text_document_semantic_tokens_full_delta_async(
        types.SemanticTokensDeltaParams(text_document=ident, previous_result_id=first.result_id))
    assert isinstance(delta, types.SemanticTokensDelta) and len(delta.edits) == 1
    data = list(first.data)
    for edit in delta.edits:
        data[edit.start:edit.start + edit.delete_count] = edit.data or []
    assert data == list((await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=ident))).data)
    assert len(delta.edits[0].data or []) < len(data) // 4
    # an id the server does not have: the whole answer
    whole = await client.text_document_semantic_tokens_full_delta_async(
        types.SemanticTokensDeltaParams(text_document=ident, previous_result_id="gone"))
    assert isinstance(whole, types.SemanticTokens) and list(whole.data) == data


async def test_results_follow_edits(client):
    """The per-rung results kept from one version to the next (rungs unchanged
    or moved) equal those of the same text opened afresh."""
    text = example_text()
    doc = Doc(client, new_uri(), text)
    await doc.diagnostics()

    async def everything(uri):
        ident = td(uri)
        return (await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=ident)),
                await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=ident)),
                (await client.text_document_semantic_tokens_full_async(
                    types.SemanticTokensParams(text_document=ident))).data)

    await everything(doc.uri)
    line = doc.find("0002|").line
    edits = [
        lambda: doc.change(line + 1, 0, line + 1, 0, "    ||                |" + " " * 51 + "||\n"),  # a line in rung 2
        lambda: doc.change(line + 1, 0, line + 2, 0, ""),  # and away again
        lambda: doc.change(2, 0, 2, 0, ""),  # nothing
        lambda: doc.change(line - 3, 0, line - 3, 0, "    ||" + " " * 68 + "||\n" * 1),  # a blank line above
        lambda: doc.change(doc.find("Cruns").line, 0, doc.find("Cruns").line, 0, ""),
    ]
    for edit in edits:
        edit()
        await doc.diagnostics()
        fresh = Doc(client, new_uri(), doc.text)
        await fresh.diagnostics()
        assert await everything(doc.uri) == await everything(fresh.uri)


async def test_results_follow_edits_made_between_two_requests(client):
    """A rung moved by several edits in a row, none of them followed by a
    request, takes its results from where they were last worked out (the
    document's results are shared by its versions, a moved rung's shifted
    when a feature first asks): the same as the text opened afresh. The
    edits come right after the open of 400 rungs, while the server works its
    answers out ahead of the requests."""
    doc = Doc(client, new_uri(), big_text(400))
    line = doc.find("0002|").line
    blank = "    ||" + " " * 68 + "||\n"
    doc.change(line - 3, 0, line - 3, 0, blank)  # lines added above rung 2 ...
    doc.change(line - 3, 0, line - 3, 0, blank + blank)
    doc.change(line - 3, 0, line - 2, 0, "")  # ... one taken away again
    doc.change(line + 3, 0, line + 3, 0, "    ||                |" + " " * 51 + "||\n")  # a line in rung 2
    await doc.diagnostics()
    fresh = Doc(client, new_uri(), doc.text)
    await fresh.diagnostics()
    ident, again = td(doc.uri), td(fresh.uri)
    assert (await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=ident))
            == await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=again)))
    assert ((await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(text_document=ident))).data
            == (await client.text_document_semantic_tokens_full_async(
                types.SemanticTokensParams(text_document=again))).data)
    assert (await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=ident))
            == await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=again)))
