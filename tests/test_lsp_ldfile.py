"""End to end on LDmicro `.ld` files: diagnostics, hover, symbols, completion,
semantic tokens, a quick fix (a rename in place), and simulation."""

from __future__ import annotations

import pytest
from lsprotocol import types
from test_lsp_support import Doc, apply_edits, hover_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()

LD = """LDmicro0.2
MICRO=Atmel AVR ATmega328 28-PDIP
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=2400 Hz

IO LIST
    Xbutton at 4 0 0
    Xlamp at 5 0 0
END

PROGRAM
RUNG
  CONTACTS Xbutton 0 0
  TON Tdebounce 50000 0
  COIL Xlamp 0 0 0 0
END
"""


async def test_ld_features(client):
    doc = Doc(client, new_uri(suffix=".ld"), LD, language="ldmicro")
    found = await doc.diagnostics()
    assert "LD102" in [d.code for d in found]
    text = hover_text(await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=doc.find("TON"))))
    assert "turn-on delay" in text
    text = hover_text(await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=doc.find("RUNG"))))
    assert "Xlamp := TON[Tdebounce, 50 ms](Xbutton)" in text
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=td(doc.uri)))
    assert [s.name for s in symbols] == ["Rung 1"]
    items = await client.text_document_completion_async(types.CompletionParams(
        text_document=td(doc.uri), position=types.Position(line=doc.find("COIL").line, character=2)))
    assert "CTU" in {i.label for i in items.items}
    tokens = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=td(doc.uri)))
    assert tokens.data
    coil = next(d for d in found if d.code == "LD102")
    actions = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=td(doc.uri), range=coil.range, context=types.CodeActionContext(diagnostics=[coil])))
    fix = next(a for a in actions if a.title.startswith("Rename 'Xlamp' to 'Ylamp'"))
    changes = fix.edit.document_changes[0].edits if fix.edit.document_changes else fix.edit.changes[doc.uri]
    new = apply_edits(doc.text, changes)
    assert new == LD.replace("Xlamp", "Ylamp")
    doc.replace_all(new)
    assert "LD102" not in [d.code for d in await doc.diagnostics()]
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.start", arguments=[doc.uri]))
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.set", arguments=[doc.uri, "Xbutton", 1]))
    state = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.step", arguments=[doc.uri]))
    assert state["energized"] and state["energized"][0]["start"]["line"] == doc.find("CONTACTS").line
    await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.sim.stop", arguments=[doc.uri]))
