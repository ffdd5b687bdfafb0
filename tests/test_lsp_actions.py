"""End to end: quick fixes, structural edits of the drawing, conversion."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from builders import NOT_COMPILED_LD
from lsprotocol import types
from test_lsp_support import Doc, apply_edits, drawing_text, example_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


def edits_of(action: types.CodeAction, uri: str) -> list[types.TextEdit]:
    edit = action.edit
    if edit.document_changes:
        return [e for change in edit.document_changes for e in change.edits]
    return edit.changes[uri]


async def actions_at(client, doc: Doc, start: types.Position, end: types.Position | None = None,
                     diagnostics=(), only=None) -> list[types.CodeAction]:
    result = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=td(doc.uri), range=types.Range(start=start, end=end or start),
        context=types.CodeActionContext(diagnostics=list(diagnostics), only=only)))
    return [_action(a) for a in result or []]


def _action(found) -> types.CodeAction:
    """lsprotocol's client-side converter reads any code action holding a
    `command` as a bare Command (its hook only looks for the key); undo that."""
    if isinstance(found, types.Command) and found.command.startswith("{"):
        import ast

        inner = ast.literal_eval(found.command)
        return types.CodeAction(title=found.title, command=types.Command(**inner))
    return found


async def test_quick_fix_renames_an_input_used_as_a_coil(client):
    # the properties that name it are renamed with it
    doc = Doc(client, new_uri(), example_text().replace("Yhorn", "Xhorn"))
    found = await doc.diagnostics()
    assert [d.code for d in found] == ["LD102"]
    actions = await actions_at(client, doc, found[0].range.start, found[0].range.end, found, only=["quickfix"])
    titles = [a.title for a in actions]
    assert titles[:3] == ["Rename 'Xhorn' to 'Yhorn' (digital output)", "Rename 'Xhorn' to 'Rhorn' (internal relay)",
                          "Rename 'Xhorn' to 'Mhorn' (Modbus coil)"]
    assert actions[0].is_preferred
    new = apply_edits(doc.text, edits_of(actions[0], doc.uri))
    doc.replace_all(new)
    assert await doc.diagnostics() == []
    assert new == example_text()


async def test_quick_fix_for_a_misspelt_part(client):
    doc = Doc(client, new_uri(), example_text().replace("ATmega328 28-PDIP", "ATmega329 28-PDIP"))
    found = await doc.diagnostics()
    assert [d.code for d in found] == ["LD409"]
    actions = await actions_at(client, doc, found[0].range.start, found[0].range.end, found, only=["quickfix"])
    assert actions[0].title == "Change the part to 'Atmel AVR ATmega328 28-PDIP'"
    doc.replace_all(apply_edits(doc.text, edits_of(actions[0], doc.uri)))
    assert await doc.diagnostics() == []


async def structural(client, doc, needle, title, occurrence=0, end_needle=None):
    start = doc.find(needle, occurrence)
    end = None
    if end_needle:
        e = doc.find(end_needle)
        end = types.Position(line=e.line, character=e.character + len(end_needle))
    actions = await actions_at(client, doc, types.Position(line=start.line, character=start.character + 1), end)
    chosen = [a for a in actions if a.title == title]
    assert chosen, [a.title for a in actions]
    new = apply_edits(doc.text, edits_of(chosen[0], doc.uri))
    doc.replace_all(new)
    return new


async def rung_logic(client, doc) -> list[str]:
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=td(doc.uri)))
    diagram = next(s for s in symbols if s.name == "LADDER DIAGRAM")
    return [r.detail for r in diagram.children]


async def test_delete_and_move(client):
    doc = Doc(client, new_uri(), example_text())
    await structural(client, doc, "]/[", "Delete contact 'Ymotor'", occurrence=1)
    assert (await doc.diagnostics()) == []
    assert (await rung_logic(client, doc))[3] == "Yhorn := Rrun"
    doc2 = Doc(client, new_uri(), example_text())
    await structural(client, doc2, "]/[", "Move contact 'Ymotor' left", occurrence=1)
    assert (await doc2.diagnostics()) == []
    assert (await rung_logic(client, doc2))[3] == "Yhorn := !Ymotor & Rrun"


async def test_insert_elements_and_rungs(client):
    doc = Doc(client, new_uri(), example_text())
    await structural(client, doc, "]/[", "Insert TON after contact 'Ymotor'", occurrence=1)
    found = await doc.diagnostics()
    assert not [d for d in found if d.code.startswith("LD0")]
    assert (await rung_logic(client, doc))[3] == "Yhorn := TON[Tnew, 100 ms](Rrun & !Ymotor)"
    await structural(client, doc, "0004", "Insert a rung below")
    logic = await rung_logic(client, doc)
    assert logic[4] == "Ynew := Xnew" and len(logic) == 5
    await structural(client, doc, "0002", "Insert a comment rung above")
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=td(doc.uri)))
    diagram = next(s for s in symbols if s.name == "LADDER DIAGRAM")
    assert diagram.children[1].name == "Rung 2: ; comment" and len(diagram.children) == 6


async def test_parallel_branch_around_a_selection(client):
    doc = Doc(client, new_uri(), example_text())
    line = doc.find("0004||").line
    start = types.Position(line=line, character=doc.lines[line].index("] ["))
    end = types.Position(line=line, character=doc.lines[line].index("]/[") + 3)
    actions = await actions_at(client, doc, start, end)
    chosen = next(a for a in actions if a.title == "Add a parallel branch (contact) around 2 elements")
    doc.replace_all(apply_edits(doc.text, edits_of(chosen, doc.uri)))
    found = await doc.diagnostics()
    assert not [d for d in found if d.code.startswith("LD0")], found
    assert (await rung_logic(client, doc))[3] == "Yhorn := Rrun & !Ymotor | Xnew"


async def test_convert_to_ld_and_back(client, tmp_path):
    source = tmp_path / "conveyor.ladder"
    source.write_text(example_text(), encoding="utf-8")
    doc = Doc(client, source.as_uri(), example_text())
    await doc.diagnostics()
    actions = await actions_at(client, doc, types.Position(line=0, character=0), only=["source"])
    assert actions[0].command.command == "ladder.convert"
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.convert", arguments=actions[0].command.arguments))
    written = Path(result["path"])
    assert written == tmp_path / "conveyor.ld" and written.read_bytes().startswith(b"LDmicro0.")
    assert b"\r\n" in written.read_bytes()
    ld = Doc(client, written.as_uri(), written.read_bytes().decode("cp1252"), language="ldmicro")
    assert await ld.diagnostics() == []
    source.unlink()
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.convert", arguments=[ld.uri, "ladder"]))
    assert Path(result["path"]).read_text(encoding="utf-8") == drawing_text()


async def test_convert_refuses_bad_arguments(client):
    doc = Doc(client, new_uri(), example_text())
    with pytest.raises(Exception) as problem:
        await client.workspace_execute_command_async(types.ExecuteCommandParams(
            command="ladder.convert", arguments=[doc.uri, "hex"]))
    assert "target must be" in str(problem.value)


async def test_build_writes_the_hex_beside_the_file(client, tmp_path):
    source = tmp_path / "conveyor.ladder"
    source.write_text(example_text(), encoding="utf-8")
    doc = Doc(client, source.as_uri(), example_text())
    await doc.diagnostics()
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.build", arguments=[doc.uri]))
    assert result["ok"] is True and result["summary"].startswith("ATmega328P: flash ")
    assert Path(result["hex"]) == tmp_path / "conveyor.hex" and (tmp_path / "conveyor.hex").read_text().startswith(":")


async def test_build_errors_and_compile_on_save(client, tmp_path):
    text = example_text().replace("Atmel AVR ATmega328 28-PDIP", "St ARM STM32F40X 144-LQFP")  # no pin data
    text = text.split("I/O ASSIGNMENT:")[0]
    source = tmp_path / "pic.ladder"
    source.write_text(text, encoding="utf-8")
    doc = Doc(client, source.as_uri(), text)
    await doc.diagnostics()
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.build", arguments=[doc.uri]))
    assert result["ok"] is False and result["hex"] is None and "cannot compile" in result["summary"]
    # compile on save: an AVR program gets its HEX when saved
    good = tmp_path / "saved.ladder"
    good.write_text(example_text(), encoding="utf-8")
    saved = Doc(client, good.as_uri(), example_text())
    await saved.diagnostics()
    client.text_document_did_save(types.DidSaveTextDocumentParams(text_document=td(saved.uri)))
    import asyncio

    for _ in range(200):
        if (tmp_path / "saved.hex").exists():
            break
        await asyncio.sleep(0.05)
    assert (tmp_path / "saved.hex").read_text().startswith(":")


async def test_an_instruction_the_family_cannot_compile_is_an_error_once_built(client, tmp_path):
    source = tmp_path / "segments.ld"
    source.write_text(NOT_COMPILED_LD, encoding="utf-8")
    doc = Doc(client, source.as_uri(), NOT_COMPILED_LD, language="ldmicro")
    editing = [d for d in await doc.diagnostics() if d.code == "LD501"]
    assert [d.severity for d in editing] == [types.DiagnosticSeverity.Warning]
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.build", arguments=[doc.uri]))
    assert result["ok"] is False and "SPI" in result["summary"] and not (tmp_path / "segments.hex").exists()
    built = [d for d in await doc.diagnostics() if d.code == "LD501"]
    assert [(d.severity, d.range) for d in built] == [(types.DiagnosticSeverity.Error, editing[0].range)]


SLOW_SCAN = """LDmicro0.2
MICRO=Microchip PIC16F877 40-PDIP
CYCLE=1000 us
CRYSTAL=4000000 Hz

IO LIST
    Xgo at 21
END

PROGRAM
RUNG 1
  CONTACTS Xgo 0 0
  PARALLEL
    DIV speed distance time
    DIV rate count time
    DIV share part total
  END
END
"""


async def test_compile_on_save_reports_the_scan_time_and_warns_when_it_cannot_fit(client, tmp_path):
    import asyncio

    source = tmp_path / "slow.ld"
    source.write_text(SLOW_SCAN, encoding="utf-8")
    doc = Doc(client, source.as_uri(), SLOW_SCAN, language="ldmicro")
    assert "LD712" not in {d.code for d in await doc.diagnostics()}  # the compiler's, once it has built
    client.text_document_did_save(types.DidSaveTextDocumentParams(text_document=td(doc.uri)))
    for _ in range(200):
        logged = [m.message for m in client.log_messages if "slow.hex" in m.message]
        if logged:
            break
        await asyncio.sleep(0.05)
    assert logged and logged[0].startswith("compile on save: PIC16F877: flash ")
    assert re.search(r"; scan: at most [\d,]+ cycles = [\d,]+ µs of the 1 ms cycle \(1\d\d\.\d%\)", logged[0])
    for _ in range(200):
        overrun = [d for d in client.diagnostics.get(doc.uri, ()) if d.code == "LD712"]
        if overrun:
            break
        await asyncio.sleep(0.05)
    assert [(d.severity, d.range.start.line) for d in overrun] == [(types.DiagnosticSeverity.Warning, 11)]
    assert "more than the 1 ms cycle" in overrun[0].message
