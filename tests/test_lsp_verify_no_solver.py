"""End to end: `ladder.verify` on a server without z3 (docs/lsp-protocol.md,
"Verification"): one message that names the pip command, as `ladder verify`
gives it, and the server goes on serving."""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from lsprotocol import types
from test_lsp_simulation import command
from test_lsp_support import Doc, lsp_fixture, new_uri
from test_lsp_verify import count_lens_refreshes, motor, verified

pytestmark = pytest.mark.asyncio(loop_scope="module")
# a z3 package first on the server's path that cannot be imported, as when z3-solver is not installed
_HIDDEN = Path(tempfile.mkdtemp(prefix="textladder-no-z3-"))
(_HIDDEN / "z3").mkdir()
(_HIDDEN / "z3" / "__init__.py").write_text('raise ImportError("No module named \'z3\'")\n', encoding="utf-8")
client = lsp_fixture(env={"PYTHONPATH": str(_HIDDEN)})


async def test_without_the_solver_one_message_names_the_pip_command(client):
    count_lens_refreshes(client)
    doc = Doc(client, new_uri(), motor("never Ymotor_fwd and Ymotor_rev"))
    await doc.diagnostics()
    before = len(client.messages)
    answer = await command(client, "ladder.verify", doc.uri)
    expected = "the SMT solver z3 is not installed; install it with: pip install 'textladder[verify]'"
    assert answer == {"uri": doc.uri, "error": expected}
    assert [(m.type, m.message) for m in client.messages[before:]] == [
        (types.MessageType.Error, f"ladder verify: {expected}")]
    assert await verified(client, doc) == {}
    # still serving: the simulation runs
    state = await command(client, "ladder.sim.start", doc.uri)
    assert state["running"] is True
    await command(client, "ladder.sim.stop", doc.uri)
    doc.close()
