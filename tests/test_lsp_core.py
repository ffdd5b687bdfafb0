"""End to end over stdio: diagnostics as you type, hover, formatting."""

from __future__ import annotations

import pytest
from lsprotocol import types
from test_lsp_support import Doc, example_text, hover_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


async def test_clean_file_has_no_diagnostics(client):
    doc = Doc(client, new_uri(), example_text())
    assert await doc.diagnostics() == []


async def test_check_diagnostic_with_code(client):
    doc = Doc(client, new_uri(), example_text().replace("Yhorn", "Xhorn"))
    found = await doc.diagnostics()
    assert [d.code for d in found] == ["LD102"]
    d = found[0]
    assert d.severity == types.DiagnosticSeverity.Error and d.source == "ladder"
    line = doc.lines[d.range.start.line]
    assert line[d.range.start.character:d.range.end.character] == "Xhorn"
    # no link: the documentation ships with the repository, not at an address
    assert d.code_description is None


async def test_diagnostics_follow_typing(client):
    doc = Doc(client, new_uri(), example_text())
    assert await doc.diagnostics() == []
    at = doc.find("] [", 1)  # rung 2's second contact row... break a wire on the first symbol line
    at = doc.find("0003||-------] [")
    doc.change(at.line, at.character + 16, at.line, at.character + 17, "|")
    found = await doc.diagnostics()
    assert [d.code for d in found] == ["LD005"]
    assert found[0].range.start.line == at.line
    doc.change(at.line, at.character + 16, at.line, at.character + 17, "-")
    assert await doc.diagnostics() == []


async def test_related_information(client):
    # two names on one pin: the check points at the first assignment
    text = example_text().replace("|   5 | PD3", "|   4 | PD3")
    doc = Doc(client, new_uri(), text)
    found = await doc.diagnostics()
    with_related = [d for d in found if d.related_information]
    assert with_related, [d.code for d in found]
    info = with_related[0].related_information[0]
    assert info.location.uri == doc.uri and "Xstart" in info.message
    assert doc.lines[info.location.range.start.line].lstrip().startswith("Xstart")


async def test_hover_instruction(client):
    doc = Doc(client, new_uri(), example_text())
    position = doc.find("[TON 2 s]")
    result = await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=types.Position(line=position.line, character=position.character + 2)))
    text = hover_text(result)
    assert "TON" in text and "turn-on delay" in text and "delay" in text and "2 s" in text
    assert result.range.start.line == position.line
    assert result.range.start.character == position.character
    assert result.range.end.character == position.character + len("[TON 2 s]")


async def test_hover_name_role_pin_and_uses(client):
    doc = Doc(client, new_uri(), example_text())
    position = doc.find("Xstart", 0)
    result = await client.text_document_hover_async(types.HoverParams(text_document=td(doc.uri), position=position))
    text = hover_text(result)
    assert "digital input" in text and "pin 4" in text and "PD2" in text
    assert "Read in rung 2" in text and "Never written" in text
    position = doc.find("Rrun", 0)
    text = hover_text(await client.text_document_hover_async(
        types.HoverParams(text_document=td(doc.uri), position=position)))
    assert "internal relay" in text and "Written in rung 2 (coil 'Rrun')" in text
    assert "rung 3" in text and "rung 4" in text


async def test_hover_rung_logic(client):
    doc = Doc(client, new_uri(), example_text())
    position = doc.find("0002|")
    text = hover_text(await client.text_document_hover_async(
        types.HoverParams(text_document=td(doc.uri), position=position)))
    assert "Rrun := (Xstart | Rrun) & !Xstop" in text
    assert "Rung 2" in text


async def test_hover_header_and_io_table(client):
    doc = Doc(client, new_uri(), example_text())
    text = hover_text(await client.text_document_hover_async(
        types.HoverParams(text_document=td(doc.uri), position=doc.find("ATmega328"))))
    assert "ATmega328" in text and "I/O pins" in text
    position = doc.find("  Ymotor                     |")
    text = hover_text(await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=types.Position(line=position.line, character=position.character + 3))))
    assert "digital output" in text and "pin 19" in text


async def test_hover_nowhere_is_null(client):
    doc = Doc(client, new_uri(), example_text())
    result = await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=types.Position(line=2, character=0)))
    assert result is None


async def test_formatting(client):
    text = example_text()
    # a hand-drawn rung: short wires, no rung numbers, no right rail
    messy = text.replace(
        "    ||      Rrun            Ymotor                             Yhorn      ||\n"
        "0004||-------] [--------------]/[-------------------------------( )-------||\n",
        "    ||  Rrun    Ymotor     Yhorn\n"
        "0004||--] [-----]/[-------( )--\n")
    assert messy != text
    doc = Doc(client, new_uri(), messy)
    assert await doc.diagnostics() == []
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=td(doc.uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert edits and len(edits) <= 2
    assert doc.apply(edits) == text
    # formatted text formats to nothing
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=td(doc.uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert not edits


async def test_formatting_refuses_broken_text(client):
    text = example_text().replace("0003||-------] [", "0003||-------] [|", 1)
    doc = Doc(client, new_uri(), text)
    await doc.diagnostics()
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=td(doc.uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert not edits


async def test_not_our_files_are_ignored(client):
    doc = Doc(client, new_uri(suffix=".ld"), "SECTIONS { .text : { *(.text) } }\n", language="ld")
    result = await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=types.Position(line=0, character=3)))
    assert result is None


NON_ASCII = """LDmicro export text.
no MCU assigned, 16 MHz crystal, 10.000 ms cycle time

LADDER DIAGRAM:
    ||                                                                    ||
    ||       Xa                       var                       Ya        ||
0001||-------] [-------------------{"é😀 ok"}--------------------( )-------||
    ||                                                                    ||
    ||                                                                    ||
    ||                                                                    ||
   1||------[END]---------------------------------------------------------||
    ||                                                                    ||
    ||                                                                    ||

I/O ASSIGNMENT:
  Name                       | Type               | Pin | Port | Pin name
 ----------------------------+--------------------+-----+------+-----------
  Xa                         | digital in         |     |       |
  Ya                         | digital out        |     |       |

VAR LIST:
"""


def units(text: str, encoding: str) -> int:
    if encoding == "utf-8":
        return len(text.encode("utf-8"))
    if encoding == "utf-16":
        return len(text.encode("utf-16-le")) // 2
    return len(text)


async def test_positions_in_the_negotiated_encoding(client):
    """Neovim's profile offers UTF-8 first, VS Code's nothing (UTF-16): columns
    after `é😀` differ in both from Python's."""
    encoding = client.init_result.capabilities.position_encoding or "utf-16"
    assert encoding == ("utf-8" if client.profile == "neovim" else "utf-16")
    doc = Doc(client, new_uri(), NON_ASCII)
    await doc.diagnostics()
    line = doc.find("( )").line
    text = doc.lines[line]
    coil = text.index("( )")
    position = types.Position(line=line, character=units(text[:coil], encoding) + 1)
    result = await client.text_document_hover_async(types.HoverParams(text_document=td(doc.uri), position=position))
    assert "coil" in hover_text(result)
    assert result.range.start.character == units(text[:coil], encoding)
    assert result.range.end.character == units(text[:coil + 3], encoding)


async def test_a_diagnostic_kept_through_an_edit_is_placed_in_its_lines_new_encoding(client):
    """The server encodes a diagnostic once while its line is ASCII; the
    same diagnostic on a line an edit made non-ASCII (`Xa` typed over as
    `Xé` left of the coil) is placed in the new line's code units, and back."""
    encoding = client.init_result.capabilities.position_encoding or "utf-16"
    text = NON_ASCII.replace("Ya        ||", "Xb        ||").replace(
        "  Ya                         | digital out        |     |       |\n", "")
    doc = Doc(client, new_uri(), text)
    at = doc.find("Xa")
    for typed in ("a", "é", "a"):
        doc.change(at.line, at.character + 1, at.line, at.character + 2, typed)
        coil_on_input = [d for d in await doc.diagnostics() if d.code == "LD102"]
        line = doc.lines[at.line]
        coil = line.index("Xb")
        assert [(d.range.start, d.range.end) for d in coil_on_input] == [(
            types.Position(line=at.line, character=units(line[:coil], encoding)),
            types.Position(line=at.line, character=units(line[:coil + 2], encoding)))]
