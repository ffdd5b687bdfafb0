"""End to end: a request about a document that a later edit (read before the
request was worked out) has changed is answered ContentModified at once, so
work queued while the client types faster than the server answers is
dropped, not piled up; a request made after the edit is answered as usual."""

from __future__ import annotations

import asyncio

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcContentModified, JsonRpcException
from test_lsp_incremental import big_text
from test_lsp_support import Doc, hover_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


async def test_a_request_made_stale_by_an_edit_is_answered_content_modified(client):
    doc = Doc(client, new_uri(), big_text(2000))  # the server reads and checks it for a while
    position = doc.find("Xstart")
    stale = asyncio.ensure_future(client.text_document_hover_async(
        types.HoverParams(text_document=td(doc.uri), position=position)))
    await asyncio.sleep(0)  # the hover is sent
    line = doc.find("0004||").line
    doc.change(line, 10, line, 11, "-")  # arrives while the server is still busy with the open
    with pytest.raises(JsonRpcException) as answer:
        await stale
    assert answer.value.code == JsonRpcContentModified.CODE
    fresh = await client.text_document_hover_async(types.HoverParams(text_document=td(doc.uri), position=position))
    assert "Xstart" in hover_text(fresh)
    await doc.diagnostics()
