"""End to end: the simulation commands and notification of docs/lsp-protocol.md,
inlay hints and hover while it runs, and editing during a simulation."""

from __future__ import annotations

import asyncio

import pytest
from corpus import CORPUS
from lsprotocol import types
from test_lsp_support import Doc, example_text, hover_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()
HELLO = CORPUS / "ldmicro" / "sample" / "hello.ld"  # sends "Hello, world:     N\r\n" every second


async def command(client, name: str, *arguments):
    return await client.workspace_execute_command_async(types.ExecuteCommandParams(
        command=name, arguments=list(arguments)))


async def last_state(client, uri: str, count_before: int, timeout: float = 5.0) -> dict:
    loop = asyncio.get_running_loop()
    deadline = loop.time() + timeout
    while loop.time() < deadline:
        mine = [s for s in client.sim_states[count_before:] if s["uri"] == uri]
        if mine:
            return mine[-1]
        await asyncio.sleep(0.01)
    raise AssertionError("no ladder/simulationState notification")


def glyphs(doc: Doc, state: dict) -> list[str]:
    out = []
    for r in state["energized"]:
        line = doc.lines[r["start"]["line"]]
        out.append(line[r["start"]["character"]:r["end"]["character"]])
    return out


async def test_start_step_set_and_notifications(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    before = len(client.sim_states)
    state = await command(client, "ladder.sim.start", doc.uri)
    assert state["running"] is True and state["realtime"] is False
    assert state["scan"] == 1 and state["timeMs"] == 10.0 and state["error"] is None
    assert state["values"]["Xstart"] == 0 and state["values"]["Rrun"] == 0
    pushed = await last_state(client, doc.uri, before)
    assert pushed == state
    # Xstop is normally closed: its contact passes power only when its input does
    assert glyphs(doc, state) == []
    state = await command(client, "ladder.sim.set", doc.uri, "Xstart", 1)
    assert state["values"]["Xstart"] == 1 and state["values"]["Rrun"] == 0  # no scan yet
    state = await command(client, "ladder.sim.step", doc.uri, 1)
    assert state["values"]["Rrun"] == 1 and state["scan"] == 2
    lit = glyphs(doc, state)
    assert lit.count("] [") >= 2 and "]/[" in lit and "( )" in lit
    state = await command(client, "ladder.sim.toggle", doc.uri, "Xstart")
    assert state["values"]["Xstart"] == 0
    state = await command(client, "ladder.sim.runFor", doc.uri, 2500)
    assert state["values"]["Rrun"] == 1 and state["values"]["Ymotor"] == 1 and state["values"]["Yhorn"] == 0
    assert state["timeMs"] == pytest.approx(2520.0)
    before = len(client.sim_states)
    assert await command(client, "ladder.sim.stop", doc.uri) == {}
    stopped = await last_state(client, doc.uri, before)
    assert stopped["running"] is False and stopped["energized"] == [] and stopped["values"] == {}


async def test_run_until_and_reset(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    await command(client, "ladder.sim.start", doc.uri)
    await command(client, "ladder.sim.set", doc.uri, "Xstart", 1)
    state = await command(client, "ladder.sim.runUntil", doc.uri, "Ymotor = 1")
    assert state["reached"] is True and state["values"]["Ymotor"] == 1
    assert 2000 <= state["timeMs"] <= 2100
    state = await command(client, "ladder.sim.runUntil", doc.uri, "Cruns >= 2", 500)
    assert state["reached"] is False
    state = await command(client, "ladder.sim.reset", doc.uri)
    assert state["scan"] == 0 and state["timeMs"] == 0 and state["values"]["Rrun"] == 0
    with pytest.raises(Exception) as problem:
        await command(client, "ladder.sim.runUntil", doc.uri, "Ymotor is on")
    assert "cannot read the condition" in str(problem.value)
    with pytest.raises(Exception) as problem:
        await command(client, "ladder.sim.set", doc.uri, "Xnothing", 1)
    assert "Xnothing" in str(problem.value)
    await command(client, "ladder.sim.stop", doc.uri)


async def test_realtime(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    await command(client, "ladder.sim.start", doc.uri)
    before = len(client.sim_states)
    state = await command(client, "ladder.sim.runRealtime", doc.uri, True)
    assert state["realtime"] is True
    await asyncio.sleep(0.6)
    pushed = [s for s in client.sim_states[before:] if s["uri"] == doc.uri]
    assert len(pushed) >= 3
    times = [s["timeMs"] for s in pushed]
    assert times == sorted(times) and times[-1] > 200
    assert len(pushed) <= 0.6 * 10 + 3  # at most about 10 a second
    state = await command(client, "ladder.sim.runRealtime", doc.uri, False)
    assert state["realtime"] is False
    await asyncio.sleep(0.3)
    count = len(client.sim_states)
    await asyncio.sleep(0.3)
    assert len(client.sim_states) == count  # stopped pushing
    await command(client, "ladder.sim.stop", doc.uri)


async def test_inlay_hints_and_hover_show_values(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    hints = await client.text_document_inlay_hint_async(types.InlayHintParams(
        text_document=td(doc.uri), range=types.Range(start=types.Position(line=0, character=0),
                                                      end=types.Position(line=40, character=0))))
    assert not hints  # no simulation, no hints
    await command(client, "ladder.sim.start", doc.uri)
    await command(client, "ladder.sim.set", doc.uri, "Xstart", 1)
    await command(client, "ladder.sim.step", doc.uri)
    hints = await client.text_document_inlay_hint_async(types.InlayHintParams(
        text_document=td(doc.uri), range=types.Range(start=types.Position(line=0, character=0),
                                                      end=types.Position(line=40, character=0))))
    shown = {}
    for hint in hints:
        line = doc.lines[hint.position.line]
        assert hint.position.character == len(line) and line.endswith("||")  # after the rail, never inside
        shown.update(pair.split("=") for pair in hint.label.split())
    assert shown["Rrun"] == "1" and shown["Xstop"] == "0"
    text = hover_text(await client.text_document_hover_async(types.HoverParams(
        text_document=td(doc.uri), position=doc.find("Rrun"))))
    assert "Rrun = 1" in text
    await command(client, "ladder.sim.stop", doc.uri)


async def test_editing_during_a_simulation_keeps_the_state(client):
    doc = Doc(client, new_uri(), example_text())
    await doc.diagnostics()
    await command(client, "ladder.sim.start", doc.uri)
    await command(client, "ladder.sim.set", doc.uri, "Xstart", 1)
    await command(client, "ladder.sim.step", doc.uri, 2)
    await command(client, "ladder.sim.runRealtime", doc.uri, True)
    before = len(client.sim_states)
    # rename the horn while it runs: a new name, the others keep their values
    doc.replace_all(doc.text.replace("Yhorn", "Ybuzzer"))
    await doc.diagnostics()
    await asyncio.sleep(0.3)
    state = await last_state(client, doc.uri, before)
    assert "Ybuzzer" in state["values"] and "Yhorn" not in state["values"]
    assert state["values"]["Rrun"] == 1 and state["error"] is None
    assert state["timeMs"] > 20
    # a broken edit: the last good program keeps running
    doc.replace_all(doc.text.replace("0003||-------] [", "0003||-------] [|", 1))
    await doc.diagnostics()
    await asyncio.sleep(0.3)
    state = client.sim_states[-1]
    assert state["running"] is True and "errors" in (state["error"] or "")
    await command(client, "ladder.sim.stop", doc.uri)


async def test_the_state_carries_what_the_uart_sent(client):
    doc = Doc(client, new_uri(suffix=".ld"), HELLO.read_text(encoding="ascii"), language="ldmicro")
    await doc.diagnostics()
    state = await command(client, "ladder.sim.start", doc.uri)
    assert state["uart"] == {"sent": 1, "messages": [{"timeMs": 0.0, "text": '"H"'}]}
    state = await command(client, "ladder.sim.runFor", doc.uri, 1100)
    # the messages as `ladder sim --watch uart` prints them, the one under way last
    assert state["uart"]["sent"] == 22 + 10
    assert state["uart"]["messages"] == [{"timeMs": 0.0, "text": '"Hello, world:      1\\r\\n"'},
                                         {"timeMs": 1010.0, "text": '"Hello, wor"'}]
    state = await command(client, "ladder.sim.reset", doc.uri)
    assert state["uart"] == {"sent": 0, "messages": []}
    before = len(client.sim_states)
    await command(client, "ladder.sim.stop", doc.uri)
    assert (await last_state(client, doc.uri, before))["uart"] == {"sent": 0, "messages": []}


async def test_commands_need_a_running_simulation_and_a_good_program(client):
    doc = Doc(client, new_uri(), example_text())
    with pytest.raises(Exception) as problem:
        await command(client, "ladder.sim.step", doc.uri)
    assert "no simulation" in str(problem.value)
    broken = Doc(client, new_uri(), example_text().replace("0003||-------] [", "0003||-------] [|", 1))
    await broken.diagnostics()
    with pytest.raises(Exception) as problem:
        await command(client, "ladder.sim.start", broken.uri)
    assert "errors" in str(problem.value)
