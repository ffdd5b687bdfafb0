"""What Windows clients send the server: drive-letter and UNC file URIs, and
files with CRLF line ends (LDmicro writes its `.ld` files so, and so may an
editor on Windows). There is no Windows machine here: the URI readings are
checked with the Windows flavour of pathlib (`PureWindowsPath`), as a server
on Windows reads them, and the CRLF files go through the real server."""

from __future__ import annotations

from pathlib import Path, PurePosixPath, PureWindowsPath

import pytest
from lsprotocol import types
from pygls import uris
from test_lsp_ldfile import LD
from test_lsp_support import Doc, apply_edits, example_text, lsp_fixture, new_uri, td

from lang.textform.formatter import format_text
from lsp.documents import LADDER, file_path, language_of
from lsp.documents import LD as LD_KIND

client = lsp_fixture()
on_server = pytest.mark.asyncio(loop_scope="module")

HEADER_LD = "LDmicro0.2\r\nMICRO=Atmel AVR ATmega328 28-PDIP\r\n"
HEADER_TEXT = "LDmicro export text.\r\n"

# URI as a client sends it -> the file a server on Windows opens
WINDOWS_URIS = {
    # VS Code: the drive letter lower case, its colon escaped
    "file:///c%3A/Users/me/prog.ladder": r"c:\Users\me\prog.ladder",
    # Neovim and others: the colon as it is
    "file:///C:/Users/me/prog.ladder": r"C:\Users\me\prog.ladder",
    "file:///D:/PLC%20programs/m%C3%B6tor%20%231.ld": r"d:\PLC programs\mötor #1.ld",
    # backslashes escaped inside the URI, as some clients write them
    "file:///C:%5CUsers%5Cme%5Cprog.ladder": r"c:\Users\me\prog.ladder",
    # a UNC share: the server is the URI's authority
    "file://plc-server/share/line%201/prog.ladder": r"\\plc-server\share\line 1\prog.ladder",
}


@pytest.fixture(params=[False, True], ids=["posix-pygls", "windows-pygls"])
def windows_pygls(request, monkeypatch):
    """pygls turns `/` into `\\` only on Windows; the reading must not depend on it."""
    monkeypatch.setattr(uris, "IS_WIN", request.param)


@pytest.mark.parametrize("uri", WINDOWS_URIS)
def test_windows_uris_name_the_file(uri, windows_pygls):
    path = file_path(uri, PureWindowsPath)
    assert path == PureWindowsPath(WINDOWS_URIS[uri])  # Windows compares without case
    assert path is not None and path.is_absolute()


def test_the_hex_and_the_converted_file_land_beside_the_source():
    share = file_path("file://plc-server/share/line%201/prog.ladder", PureWindowsPath)
    assert share is not None and share.drive == r"\\plc-server\share"
    assert str(share.with_suffix(".hex")) == r"\\plc-server\share\line 1\prog.hex"
    drive = file_path("file:///c%3A/Users/me/prog.ladder", PureWindowsPath)
    assert drive is not None and str(drive.with_suffix(".ld")) == r"c:\Users\me\prog.ld"
    assert [str(p) for p in drive.parents] == [r"c:\Users\me", r"c:\Users", "c:\\"]  # where ladder.toml is looked for


def test_uris_that_name_no_file():
    assert file_path("untitled:Untitled-1", PureWindowsPath) is None
    assert file_path("file:///", PureWindowsPath) is None
    assert file_path("file:///c%3A/", PureWindowsPath) is None
    # a drive letter is no absolute path on Linux: nothing is written relative to the server's folder
    assert file_path("file:///c%3A/Users/me/prog.ladder", PurePosixPath) is None
    assert file_path("file:///home/me/a%20b%20%231.ladder", PurePosixPath) == PurePosixPath("/home/me/a b #1.ladder")


@pytest.mark.parametrize("uri, text, kind", [
    ("file:///c%3A/Users/me/PROG.LADDER", "", LADDER),
    ("file:///C:/PLC/MOTOR.LD", HEADER_LD, LD_KIND),
    ("file:///C:/PLC/linker.ld", "OUTPUT_FORMAT(elf32-avr)\r\n", None),
    ("file:///C:%5Cmy.progs%5Cexport.TXT", HEADER_TEXT, LADDER),
    ("file:///C:%5Cmy.progs%5Cnotes", HEADER_TEXT, None),
    ("file://plc-server/share/motor.ld", HEADER_LD, LD_KIND),
])
def test_language_by_windows_name(uri, text, kind):
    assert language_of(uri, text) == kind


def crlf(text: str) -> str:
    return text.replace("\r\n", "\n").replace("\n", "\r\n")


@on_server
async def test_crlf_ladder_diagnostics_follow_typing(client):
    lf = example_text().replace("Yhorn", "Xhorn")
    doc = Doc(client, new_uri(), crlf(lf))
    found = await doc.diagnostics()
    assert [d.code for d in found] == ["LD102"]
    line = doc.lines[found[0].range.start.line]
    assert line[found[0].range.start.character:found[0].range.end.character] == "Xhorn"
    assert found[0].range.start.line == lf.splitlines().index(line)
    at = doc.find("0003||-------] [")
    doc.change(at.line, at.character + 16, at.line, at.character + 17, "|")
    found = await doc.diagnostics()
    assert "LD005" in [d.code for d in found]
    assert next(d for d in found if d.code == "LD005").range.start.line == at.line
    doc.change(at.line, at.character + 16, at.line, at.character + 17, "-")
    assert [d.code for d in await doc.diagnostics()] == ["LD102"]


@on_server
async def test_crlf_ladder_formatting_and_a_fix_keep_crlf(client):
    messy = example_text().replace(
        "    ||      Rrun            Ymotor                             Yhorn      ||\n"
        "0004||-------] [--------------]/[-------------------------------( )-------||\n",
        "    ||  Rrun    Ymotor     Yhorn\n"
        "0004||--] [-----]/[-------( )--\n").replace("Yhorn", "Xhorn")
    doc = Doc(client, new_uri(), crlf(messy))
    await doc.diagnostics()
    edits = await client.text_document_formatting_async(types.DocumentFormattingParams(
        text_document=td(doc.uri), options=types.FormattingOptions(tab_size=4, insert_spaces=True)))
    assert edits
    assert doc.apply(edits) == crlf(format_text(messy)[0] or "")  # `ladder fmt`'s, in CRLF
    ld102 = next(d for d in await doc.diagnostics() if d.code == "LD102")
    actions = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=td(doc.uri), range=ld102.range, context=types.CodeActionContext(diagnostics=[ld102])))
    fix = next(a for a in actions if a.title.startswith("Rename 'Xhorn' to 'Yhorn'"))
    edits = fix.edit.document_changes[0].edits if fix.edit.document_changes else fix.edit.changes[doc.uri]
    fixed = doc.apply(edits)
    assert "Xhorn" not in fixed and fixed.count("\n") == fixed.count("\r\n")
    assert await doc.diagnostics() == []


@on_server
async def test_crlf_ld_file(client):
    doc = Doc(client, new_uri(suffix=".ld"), crlf(LD), language="ldmicro")
    found = await doc.diagnostics()
    coil = next(d for d in found if d.code == "LD102")
    assert coil.range.start.line == doc.find("COIL Xlamp").line
    assert doc.lines[coil.range.start.line][coil.range.start.character:coil.range.end.character] == "Xlamp"
    actions = await client.text_document_code_action_async(types.CodeActionParams(
        text_document=td(doc.uri), range=coil.range, context=types.CodeActionContext(diagnostics=[coil])))
    fix = next(a for a in actions if a.title.startswith("Rename 'Xlamp' to 'Ylamp'"))
    edits = fix.edit.document_changes[0].edits if fix.edit.document_changes else fix.edit.changes[doc.uri]
    assert apply_edits(doc.text, edits) == crlf(LD.replace("Xlamp", "Ylamp"))
    at = doc.find("COIL")
    items = await client.text_document_completion_async(types.CompletionParams(
        text_document=td(doc.uri), position=types.Position(line=at.line, character=2)))
    assert "CTU" in {i.label for i in items.items}
    line = doc.find("COIL Xlamp")
    doc.change(line.line, line.character + 5, line.line, line.character + 6, "Y")
    assert "LD102" not in [d.code for d in await doc.diagnostics()]


@on_server
async def test_a_folder_whose_name_needs_escapes(client, tmp_path):
    """The URI of `my progs/mötor #1.ladder` is percent-escaped: the project's
    settings are found, and the converted file is written beside the source."""
    folder = tmp_path / "my progs ä"
    folder.mkdir()
    (folder / "ladder.toml").write_text('[diagnostics]\nLD130 = "error"\n', encoding="utf-8")
    source = folder / "mötor #1.ladder"
    text = crlf(example_text().replace("Xstop", "Rnever", 1))  # a relay never written: LD130
    source.write_bytes(text.encode("utf-8"))
    uri = source.as_uri()
    assert "%20" in uri and "%23" in uri
    doc = Doc(client, uri, text)
    found = await doc.diagnostics()
    assert [(d.code, d.severity) for d in found if d.code == "LD130"] == [("LD130", types.DiagnosticSeverity.Error)]
    (folder / "ladder.toml").unlink()
    doc.replace_all(crlf(example_text()))
    assert await doc.diagnostics() == []
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.convert", arguments=[uri, "ld"]))
    assert Path(result["path"]) == folder / "mötor #1.ld"
    assert Path(result["path"]).read_bytes().startswith(b"LDmicro0.")
