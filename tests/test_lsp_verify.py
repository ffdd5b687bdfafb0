"""End to end: `ladder verify` in the editor (docs/lsp-protocol.md,
"Verification"): the lenses of the PROPERTIES section, each result as a
diagnostic on its property's line (proved, failing at a scan, holding up to
the bound), the counterexample stepped through in the simulation up to the
scan that breaks the property, what an edit does to the results, and the
server answering while it proves."""

from __future__ import annotations

import asyncio
import re
from pathlib import Path

import pytest
from lsprotocol import types
from test_lsp_actions import actions_at
from test_lsp_simulation import command
from test_lsp_support import Doc, hover_text, lsp_fixture, new_uri, td

pytestmark = pytest.mark.asyncio(loop_scope="module")
client = lsp_fixture()
MOTOR = Path(__file__).resolve().parents[1] / "examples" / "reversing-motor.ladder"
SOURCE = "ladder verify"


def motor(*properties: str) -> str:
    """The reversing motor of examples/ with these properties."""
    text = MOTOR.read_text(encoding="utf-8")
    return text[:text.index("PROPERTIES:")] + "PROPERTIES:\n" + "".join(f"  {p}\n" for p in properties)


def count_lens_refreshes(client) -> None:
    """Answer (and count) the server's requests to ask for the lenses again."""
    def refresh(params):
        client.lens_refreshes = getattr(client, "lens_refreshes", 0) + 1

    client.protocol.fm._features[types.WORKSPACE_CODE_LENS_REFRESH] = refresh


async def lenses(client, doc: Doc) -> list[tuple[int, str, types.Command]]:
    found = await client.text_document_code_lens_async(types.CodeLensParams(text_document=td(doc.uri)))
    return [(lens.range.start.line, lens.command.title, lens.command) for lens in found or []]


async def run(client, lens: types.Command, **options) -> dict:
    arguments = list(lens.arguments or [])
    if options:
        arguments = arguments[:1] + [{**(arguments[1] if len(arguments) > 1 else {}), **options}]
    return await command(client, lens.command, *arguments)


async def verified(client, doc: Doc) -> dict[int, types.Diagnostic]:
    """The verification diagnostics of the document's current version, by line."""
    found = await doc.diagnostics()
    return {d.range.start.line: d for d in found if d.source == SOURCE}


async def test_the_lenses_verify_and_each_result_is_a_diagnostic_on_its_property(client):
    count_lens_refreshes(client)
    doc = Doc(client, new_uri(), motor("never Ymotor_fwd and Ymotor_rev", "never Cstarts = 2",
                                       "reachable Ymotor_rev and Cstarts = 2"))
    await doc.diagnostics()
    refreshed = getattr(client, "lens_refreshes", 0)
    header = doc.find("PROPERTIES:").line
    commands = client.init_result.capabilities.execute_command_provider.commands
    assert {"ladder.verify", "ladder.verify.step"} <= set(commands)  # what VS Code's client registers
    shown = await lenses(client, doc)
    assert [(line, title) for line, title, _ in shown] == [
        (header, "Verify"), (header + 1, "Verify this property"), (header + 2, "Verify this property"),
        (header + 3, "Verify this property")]
    answer = await run(client, shown[0][2])
    assert answer["version"] == doc.version and len(answer["results"]) == 3
    if client.profile == "visual-studio-code":  # asked for again when it began and when it ended
        assert client.lens_refreshes >= refreshed + 2
    found = await verified(client, doc)
    assert sorted(found) == [header + 1, header + 2, header + 3]
    proved, fails, reached = found[header + 1], found[header + 2], found[header + 3]
    assert proved.severity == types.DiagnosticSeverity.Information
    assert proved.message == "proved (k = 1): never Ymotor_fwd and Ymotor_rev"
    # the range is the property, as written
    assert doc.lines[header + 1][proved.range.start.character:proved.range.end.character] == \
        "never Ymotor_fwd and Ymotor_rev"
    assert fails.severity == types.DiagnosticSeverity.Error
    assert re.match(r"fails at \d+ ms \(scan \d+\): never Cstarts = 2\nthe inputs from power-up: at 0 ms set ",
                    fails.message)
    assert reached.severity == types.DiagnosticSeverity.Information
    assert reached.message.startswith("proved: reached at 40 ms (scan 5): reachable Ymotor_rev and Cstarts = 2")
    # related places: the counter's value after the failing scan, at the counter that writes it
    scan = int(re.search(r"scan (\d+)", fails.message).group(1))
    related = {r.message: r.location.range.start.line for r in fails.related_information or []}
    assert related == {f"Cstarts = 2 after scan {scan} ({(scan - 1) * 10} ms)": doc.find("Cstarts").line}
    titles = [(line, title) for line, title, _ in await lenses(client, doc)]
    assert titles[0] == (header, "Verify again (2 proved, 1 fails)")
    assert (header + 2, "Step through the counterexample") in titles
    assert (header + 3, "Step through the witness") in titles
    assert (header + 1, "Step through the counterexample") not in titles
    doc.close()


async def test_a_property_holding_up_to_the_bound_is_a_warning_that_says_the_bound(client):
    doc = Doc(client, new_uri(), motor("never Ymotor_fwd and Ymotor_rev", "always Cstarts <= 2"))
    await doc.diagnostics()
    header = doc.find("PROPERTIES:").line
    one = next(lens for line, title, lens in await lenses(client, doc) if line == header + 2)
    answer = await run(client, one, bound=3)
    assert [r["line"] for r in answer["results"]] == [header + 2]
    found = await verified(client, doc)
    assert list(found) == [header + 2]  # only the property verified
    assert found[header + 2].severity == types.DiagnosticSeverity.Warning
    assert found[header + 2].message == ("holds up to 3 scans (not proved): always Cstarts <= 2; a longer input "
                                         "sequence might break it (verify with a larger bound)")
    # the default bound finds the third start
    await run(client, one)
    found = await verified(client, doc)
    assert found[header + 2].severity == types.DiagnosticSeverity.Error
    assert found[header + 2].message.startswith("fails at ")
    doc.close()


async def test_the_counterexample_steps_scan_by_scan_to_the_scan_that_breaks_the_property(client):
    doc = Doc(client, new_uri(), motor("never Cstarts = 2"))
    await doc.diagnostics()
    line = doc.find("never Cstarts").line
    await command(client, "ladder.verify", doc.uri)
    failing = (await verified(client, doc))[line]
    scan = int(re.search(r"scan (\d+)", failing.message).group(1))
    actions = await actions_at(client, doc, failing.range.start, failing.range.end, [failing], only=["quickfix"])
    step = [a for a in actions if a.title == "Step through the counterexample"]
    assert len(step) == 1
    state = await run(client, step[0].command)
    assert state["running"] is True and state["scan"] == 1
    assert state["replay"]["name"] == "counterexample for `never Cstarts = 2`"
    assert state["replay"]["endMs"] == (scan - 1) * 10
    counts = [state["values"]["Cstarts"]]
    while state["scan"] < scan:
        state = await command(client, "ladder.sim.step", doc.uri, 1)
        counts.append(state["values"]["Cstarts"])
    # the property holds after every scan before the one the prover named, and not after it
    assert counts[-1] == 2 and all(c < 2 for c in counts[:-1])
    assert state["replay"]["applied"] == state["replay"]["total"]
    # a reset replays it again from power-up, whatever runs the scans
    await command(client, "ladder.sim.reset", doc.uri)
    state = await command(client, "ladder.sim.runFor", doc.uri, (scan - 1) * 10)
    assert state["scan"] == scan - 1 and state["values"]["Cstarts"] < 2
    state = await command(client, "ladder.sim.step", doc.uri, 1)
    assert state["values"]["Cstarts"] == 2
    await command(client, "ladder.sim.reset", doc.uri)
    state = await command(client, "ladder.sim.runUntil", doc.uri, "Cstarts = 2", 1000)
    assert state["reached"] is True and state["scan"] == scan
    await command(client, "ladder.sim.stop", doc.uri)
    doc.close()


async def test_an_edit_drops_the_results_and_a_verification_it_overtakes_is_not_shown(client):
    doc = Doc(client, new_uri(), motor("never Ymotor_fwd and Ymotor_rev", "always Cstarts <= 50"))
    await doc.diagnostics()
    header = doc.find("PROPERTIES:").line
    await command(client, "ladder.verify", doc.uri, {"bound": 5})
    assert len(await verified(client, doc)) == 2
    doc.change(header + 1, 2, header + 1, 2, "  ")  # the property indented a little more
    assert await verified(client, doc) == {}
    titles = [title for _, title, _ in await lenses(client, doc)]
    assert titles[0] == "Verify" and not any(t.startswith("Step through") for t in titles)
    # a long verification (the 51st start is 101 scans away, each searched) while the server keeps answering
    running = asyncio.ensure_future(command(client, "ladder.verify", doc.uri, {"line": header + 2, "bound": 200}))
    loop = asyncio.get_running_loop()
    while (await lenses(client, doc))[0][1] != "Verifying…":
        assert not running.done()
        await asyncio.sleep(0.02)
    started = loop.time()
    hover = await client.text_document_hover_async(types.HoverParams(text_document=td(doc.uri),
                                                                     position=doc.find("Cstarts")))
    assert "Cstarts" in hover_text(hover) and not running.done()
    assert loop.time() - started < 1.0
    doc.change(header + 1, 0, header + 1, 0, " ")
    answer = await running
    assert answer["error"] == "the document changed while it was verified: verify it again"
    assert await verified(client, doc) == {}
    assert client.messages[-1].message == "ladder verify: the document changed while it was verified: verify it again"
    doc.close()


async def test_a_document_that_cannot_be_verified_gets_one_message(client):
    doc = Doc(client, new_uri(), motor())
    await doc.diagnostics()
    assert await lenses(client, doc) == []  # no property, no lens
    answer = await command(client, "ladder.verify", doc.uri)
    assert answer["error"].startswith("no property to verify")
    bad = Doc(client, new_uri(), motor("never Ymotor_fwd and Ynothing"))
    await bad.diagnostics()
    answer = await command(client, "ladder.verify", bad.uri)
    assert answer["error"] == "the program has errors; fix them before verifying it"
    assert client.messages[-1].type == types.MessageType.Error
    doc.close()
    bad.close()
