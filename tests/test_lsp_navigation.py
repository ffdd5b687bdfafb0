"""End to end: definition, references, document highlight, rename."""

from __future__ import annotations

import re

import pytest
from lsprotocol import types
from test_lsp_support import Doc, apply_edits, example_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


def at(doc: Doc, needle: str, occurrence: int = 0, offset: int = 1) -> types.Position:
    p = doc.find(needle, occurrence)
    return types.Position(line=p.line, character=p.character + offset)


async def test_definition_is_where_the_name_is_written(client):
    doc = Doc(client, new_uri(), example_text())
    # Rrun read in rung 3 -> the coil of rung 2
    result = await client.text_document_definition_async(types.DefinitionParams(
        text_document=td(doc.uri), position=at(doc, "Rrun", 2)))
    assert len(result) == 1
    target = result[0].range
    coil = doc.find("Rrun", 0)  # the coil's name, on rung 2's name line
    assert (target.start.line, target.start.character) == (coil.line, coil.character)
    assert doc.lines[target.start.line][target.start.character:target.end.character] == "Rrun"


async def test_definition_of_an_input_is_its_pin_row(client):
    doc = Doc(client, new_uri(), example_text())
    result = await client.text_document_definition_async(types.DefinitionParams(
        text_document=td(doc.uri), position=at(doc, "Xstart", 0)))
    assert len(result) == 1
    assert doc.lines[result[0].range.start.line].lstrip().startswith("Xstart  ")


async def test_references_and_highlight(client):
    doc = Doc(client, new_uri(), example_text())
    refs = await client.text_document_references_async(types.ReferenceParams(
        text_document=td(doc.uri), position=at(doc, "Ymotor", 0),
        context=types.ReferenceContext(include_declaration=True)))
    lines = sorted(r.range.start.line for r in refs)
    assert len(refs) == 3  # the coil, the contact of rung 4, the I/O row
    for r in refs:
        assert doc.lines[r.range.start.line][r.range.start.character:r.range.end.character] == "Ymotor"
    assert lines[-1] == doc.find("  Ymotor                     |").line
    highlights = await client.text_document_document_highlight_async(types.DocumentHighlightParams(
        text_document=td(doc.uri), position=at(doc, "Ymotor", 0)))
    kinds = sorted(h.kind for h in highlights)
    assert types.DocumentHighlightKind.Write in kinds and types.DocumentHighlightKind.Read in kinds


async def test_rename_redraws_the_rungs(client):
    doc = Doc(client, new_uri(), example_text())
    prepared = await client.text_document_prepare_rename_async(types.PrepareRenameParams(
        text_document=td(doc.uri), position=at(doc, "Rrun", 1)))
    assert prepared.placeholder == "Rrun"
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=td(doc.uri), position=at(doc, "Rrun", 1), new_name="Rrunning_motor"))
    changes = edit.document_changes[0].edits if edit.document_changes else edit.changes[doc.uri]
    new = apply_edits(doc.text, changes)
    drawing, _, properties = new.partition("PROPERTIES:")
    # the four uses in the rungs, and the properties that name it
    assert not re.search(r"\bRrun\b", new) and drawing.count("Rrunning_motor") == 4
    assert properties.count("Rrunning_motor") == len(re.findall(r"\bRrun\b", doc.text.partition("PROPERTIES:")[2])) > 0
    # still aligned: the formatter has nothing to change
    doc.replace_all(new)
    assert await doc.diagnostics() == []
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=td(doc.uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert not edits


async def test_rename_of_an_io_name_keeps_the_table(client):
    doc = Doc(client, new_uri(), example_text())
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=td(doc.uri), position=at(doc, "Xstop", 0), new_name="Xemergency_stop"))
    changes = edit.document_changes[0].edits if edit.document_changes else edit.changes[doc.uri]
    new = apply_edits(doc.text, changes)
    row = next(ln for ln in new.splitlines() if ln.lstrip().startswith("Xemergency_stop"))
    assert row.index("|") == doc.lines[doc.find("  Xstart                     |").line].index("|")  # same column
    doc.replace_all(new)
    assert await doc.diagnostics() == []


async def test_rename_refuses_bad_names(client):
    doc = Doc(client, new_uri(), example_text())
    with pytest.raises(Exception) as problem:
        await client.text_document_rename_async(types.RenameParams(
            text_document=td(doc.uri), position=at(doc, "Xstop", 0), new_name="9lives"))
    assert "not a valid name" in str(problem.value)


async def test_rename_in_an_ld_file(client):
    from pathlib import Path

    source = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "ldmicro-export" / "Tests_test-leds.ld"
    text = source.read_bytes().decode("cp1252")
    doc = Doc(client, new_uri(suffix=".ld"), text, language="ldmicro")
    position = at(doc, "Xbutton", 1)
    edit = await client.text_document_rename_async(types.RenameParams(
        text_document=td(doc.uri), position=position, new_name="Xknob"))
    changes = edit.document_changes[0].edits if edit.document_changes else edit.changes[doc.uri]
    new = apply_edits(doc.text, changes)
    assert "Xbutton" not in new and new.count("Xknob") == text.count("Xbutton")
