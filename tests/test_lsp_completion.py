"""End to end: completion of names, rungs, elements, parts and pins."""

from __future__ import annotations

import pytest
from lsprotocol import types
from test_lsp_support import Doc, apply_edits, example_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


async def complete(client, doc: Doc, position: types.Position) -> list[types.CompletionItem]:
    result = await client.text_document_completion_async(types.CompletionParams(
        text_document=td(doc.uri), position=position))
    if result is None:
        return []
    return list(result.items if hasattr(result, "items") else result)


def accept(doc: Doc, item: types.CompletionItem) -> str:
    edits = [item.text_edit] + list(item.additional_text_edits or [])
    new_text = item.text_edit.new_text
    if item.insert_text_format == types.InsertTextFormat.Snippet:
        import re

        new_text = re.sub(r"\$\{\d+:([^}]*)\}", r"\1", new_text).replace("$0", "")
        new_text = new_text.replace("\\}", "}").replace("\\$", "$").replace("\\\\", "\\")
    edits[0] = types.TextEdit(range=item.text_edit.range, new_text=new_text)
    return apply_edits(doc.text, edits)


async def test_names_filtered_by_the_prefixes_the_operand_allows(client):
    doc = Doc(client, new_uri(), example_text())
    # a coil's name: Y, R or M names only
    position = doc.find("Yhorn", 0)
    items = await complete(client, doc, types.Position(line=position.line, character=position.character + 1))
    labels = {i.label for i in items}
    assert labels == {"Yhorn", "Ymotor"}  # "Y" typed: the outputs
    position = doc.find("Yhorn", 0)
    items = await complete(client, doc, position)  # nothing typed yet
    labels = {i.label for i in items}
    assert {"Yhorn", "Ymotor", "Rrun"} <= labels
    assert not {"Xstart", "Twarn", "Cruns"} & labels


async def test_rung_snippets_on_a_blank_line(client):
    doc = Doc(client, new_uri(), example_text())
    end = doc.find("[END]")
    blank = end.line - 1  # the blank line above END
    items = await complete(client, doc, types.Position(line=blank, character=8))
    labels = [i.label for i in items]
    assert "rung: TON" in labels and "rung: contact" in labels
    ton = next(i for i in items if i.label == "rung: TON")
    new = accept(doc, ton)
    doc.replace_all(new)
    found = await doc.diagnostics()
    assert not [d for d in found if d.code.startswith("LD0")]  # it reads: only "Xnew has no pin" and such
    assert "[TON 100 ms]" in new
    symbols = await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=td(doc.uri)))
    diagram = next(s for s in symbols if s.name == "LADDER DIAGRAM")
    assert diagram.children[-1].detail == "Ynew := TON[Tnew, 100 ms](Xnew)"


async def test_insert_an_element_on_a_wire(client):
    doc = Doc(client, new_uri(), example_text())
    line = doc.find("0004||").line
    wire = doc.lines[line].index("]/[") + 8  # on the wire after the Ymotor contact
    items = await complete(client, doc, types.Position(line=line, character=wire))
    osr = next(i for i in items if i.label == "insert OSR")
    new = accept(doc, osr)
    doc.replace_all(new)
    assert await doc.diagnostics() == []
    rung4 = new.splitlines()[line]
    assert rung4.index("]/[") < rung4.index("OSR") < rung4.index("( )")


async def test_part_names_in_the_header(client):
    doc = Doc(client, new_uri(), example_text())
    position = doc.find("Atmel AVR")
    items = await complete(client, doc, types.Position(line=position.line, character=position.character + 3))
    labels = {i.label for i in items}
    assert "Atmel AVR ATmega328 28-PDIP" in labels and "Microchip PIC16F877 40-PDIP" in labels or \
        any(label.startswith("Microchip PIC16F877") for label in labels)


async def test_pins_and_ports_in_the_io_table(client):
    doc = Doc(client, new_uri(), example_text())
    row = doc.find("  Xstop                      |").line
    text = doc.lines[row]
    pin_cell = text.index("|", text.index("|") + 1) + 2
    items = await complete(client, doc, types.Position(line=row, character=pin_cell))
    assert items and items[0].label.isdigit()
    by_label = {i.label: i for i in items}
    assert by_label["5"].detail.startswith("PD3")
    # pins already taken by another name come last
    assert list(by_label).index("4") > list(by_label).index("6")
    port_cell = text.index("|", pin_cell) + 2
    items = await complete(client, doc, types.Position(line=row, character=port_cell))
    assert "PD3" in {i.label for i in items}
    new = accept(doc, by_label["6"])
    assert new.splitlines()[row] == text.replace("|   5 |", "|   6 |")


async def test_a_big_program_offers_the_first_names_and_says_there_are_more(client):
    from builders import coil, contact, program

    from ide.completion import MAX_NAMES
    from lang.textform.writer import render_program

    relays = [f"Rr{number:03d}" for number in range(MAX_NAMES + 50)]
    doc = Doc(client, new_uri(), render_program(program(*([contact("Xa"), coil(name)] for name in relays))))
    await doc.diagnostics()
    position = doc.find("Rr000")
    result = await client.text_document_completion_async(types.CompletionParams(
        text_document=td(doc.uri), position=types.Position(line=position.line, character=position.character + 2)))
    assert result.is_incomplete  # "Rr" typed: 250 relays fit
    assert [i.label for i in result.items] == relays[:MAX_NAMES]


async def test_a_longer_name_accepted_keeps_the_rail_and_the_next_names_in_their_columns(client):
    doc = Doc(client, new_uri(), example_text())
    position = doc.find("Xstop", 0)  # "Xs" typed over the contact: Xstart, a letter longer than Xstop
    line = doc.lines[position.line]
    items = await complete(client, doc, types.Position(line=position.line, character=position.character + 2))
    chosen = next(item for item in items if item.label == "Xstart")
    accepted = accept(doc, chosen).splitlines()[position.line]
    assert accepted == line.replace("Xstop ", "Xstart", 1)
    assert len(accepted) == len(line) and accepted.index("Rrun") == line.index("Rrun")
