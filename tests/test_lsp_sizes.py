"""End to end: the editor marks a program too large for its part (LD703)
on the part's name once it is built (`ladder.build`, compile on save); while
editing only the checks run."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from lsprotocol import types
from test_lsp_support import Doc, lsp_fixture

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()


async def test_a_program_too_large_for_its_part_is_marked_on_the_part_name(client, tmp_path):
    # the LD703 fixture: LUTs that need more words than the PIC12F675's 1023
    text = (Path(__file__).parent / "diagnostics" / "LD703.ladder").read_text(encoding="utf-8")
    source = tmp_path / "big.ladder"
    source.write_text(text, encoding="utf-8")
    doc = Doc(client, source.as_uri(), text)
    assert not [d for d in await doc.diagnostics() if d.code == "LD703"]
    result = await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command="ladder.build", arguments=[doc.uri]))
    assert result["ok"] is False and re.search(r"needs \d+ words of program memory; the PIC12F675 has 1023",
                                               result["summary"])
    [built] = [d for d in await doc.diagnostics() if d.code == "LD703"]
    assert built.severity == types.DiagnosticSeverity.Error and built.range.start == types.Position(1, 5)
