"""The language server as a Web Worker runs it (lsp/worker.py): whole JSON messages in, whole
JSON messages out, no standard input, on documents that are not files (untitled:, vscode-vfs:, inmemory:).
Here on CPython's event loop; tests/test_editor_web.py runs the same entry point on Pyodide
under Node and in Chromium."""

from __future__ import annotations

import asyncio
import base64
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "e2e"))
import editor_env as env
from test_harness import needs_simavr

from compiler.run.record import Event, record_pins
from lsp.worker import connect

URI = "untitled:Untitled-1"
# documents a browser has: VS Code's unsaved buffer, a file of vscode.dev's virtual file system,
# a model of an editor in a page (no suffix: the language is the client's languageId)
URIS = [URI, "vscode-vfs://github/someone/plc/lamp.ladder", "inmemory://model/1"]


class Client:
    def __init__(self, uri: str = URI) -> None:
        self.uri = uri
        self.received: list[dict] = []
        self.send_text = connect(lambda text: self.received.append(json.loads(text)))
        self.next_id = 0

    def notify(self, method: str, params: dict) -> None:
        self.send_text(json.dumps({"jsonrpc": "2.0", "method": method, "params": params}))

    async def request(self, method: str, params: dict) -> dict:
        self.next_id += 1
        ident = self.next_id
        self.send_text(json.dumps({"jsonrpc": "2.0", "id": ident, "method": method, "params": params}))
        for _ in range(500):
            for message in self.received:
                if message.get("id") == ident and "method" not in message:
                    return message
            await asyncio.sleep(0.01)
        raise AssertionError(f"no answer to {method}")

    async def diagnostics(self, version: int) -> list[dict]:
        for _ in range(500):
            for message in reversed(self.received):
                if message.get("method") == "textDocument/publishDiagnostics" and message["params"]["version"] == version:
                    return message["params"]["diagnostics"]
            await asyncio.sleep(0.01)
        raise AssertionError(f"no diagnostics for version {version}")

    async def command(self, name: str, *arguments: object) -> dict:
        return await self.request("workspace/executeCommand", {"command": name, "arguments": [self.uri, *arguments]})


async def _session(client: Client) -> None:
    await client.request("initialize", {"processId": None, "rootUri": None, "capabilities": {}})
    client.notify("initialized", {})
    client.notify("textDocument/didOpen", {"textDocument": {"uri": client.uri, "languageId": "ladder", "version": 1,
                                                             "text": env.LAMP_BAD}})


@pytest.mark.parametrize("uri", URIS)
def test_diagnostics_hover_and_simulation_through_whole_messages(uri):
    async def run() -> None:
        client = Client(uri)
        await _session(client)
        found = await client.diagnostics(1)
        assert [d["code"] for d in found] == ["LD102"] and found[0]["range"]["start"]["line"] == env.BAD_LINE
        hover = await client.request("textDocument/hover", {"textDocument": {"uri": uri},
                                                            "position": {"line": env.BAD_LINE, "character": 61}})
        assert "Xlamp" in json.dumps(hover["result"])
        client.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 2},
                                                 "contentChanges": [{"text": env.lamp_fixed()}]})
        assert await client.diagnostics(2) == []
        started = await client.command("ladder.sim.start")
        assert started["result"]["values"]["Ylamp"] == 0
        await client.command("ladder.sim.toggle", "Xstart")
        stepped = (await client.command("ladder.sim.step", 1))["result"]
        assert stepped["values"]["Ylamp"] == 1 and stepped["energized"]
        assert any(m.get("method") == "ladder/simulationState" for m in client.received)

    asyncio.run(run())


def _exported() -> list[dict]:
    """The fixed lamp program's answers to ladder.export (hex, c, ld, ladder), ladder.build,
    ladder.convert and an export to a target that does not exist."""
    async def run() -> list[dict]:
        client = Client()
        await _session(client)
        client.notify("textDocument/didChange", {"textDocument": {"uri": URI, "version": 2},
                                                 "contentChanges": [{"text": env.lamp_fixed()}]})
        await client.diagnostics(2)
        answers = [await client.command("ladder.export", target) for target in ("hex", "c", "ld", "ladder")]
        answers.append(await client.command("ladder.build"))
        answers.append(await client.command("ladder.convert", "ld"))
        answers.append(await client.command("ladder.export", "pdf"))
        return answers

    return asyncio.run(run())


def test_files_are_exported_not_written(tmp_path):
    hex_file, c_files, ld_file, ladder_file, build, convert, bad = _exported()
    assert "ATmega328" in hex_file["result"]["summary"]
    assert [f["name"] for f in hex_file["result"]["files"]] == ["Untitled-1.hex"]
    assert [f["name"] for f in c_files["result"]["files"]] == ["Untitled-1.c", "Untitled-1.h", "ladder.h"]
    ld = base64.b64decode(ld_file["result"]["files"][0]["data"])
    assert ld.startswith(b"LDmicro") and b"\r\n" in ld
    assert base64.b64decode(ladder_file["result"]["files"][0]["data"]).decode().startswith("LDmicro export text")
    for answer in (build, convert):
        assert "in the browser no file is written" in answer["error"]["message"]
    assert "target must be one of" in bad["error"]["message"]
    # the C files compile with the host's compiler
    for f in c_files["result"]["files"]:
        (tmp_path / f["name"]).write_bytes(base64.b64decode(f["data"]))
    cc = shutil.which("gcc") or shutil.which("cc")
    assert cc is not None, "a C compiler is needed (gcc)"
    out = subprocess.run([cc, "-c", "-Wall", "-o", str(tmp_path / "prog.o"), str(tmp_path / "Untitled-1.c")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr


@needs_simavr
def test_the_exported_hex_runs_in_simavr(tmp_path):
    """The lamp follows its input: Xstart low for two scans, then high."""
    (image,) = _exported()[0]["result"]["files"]
    (tmp_path / image["name"]).write_bytes(base64.b64decode(image["data"]))
    events = [Event(0, "Xstart", 0), Event(2, "Xstart", 1)]
    recording = record_pins(tmp_path / image["name"], "atmega328p", 16_000_000, 10_000, events, 5,
                            {"Xstart": "PD2", "Ylamp": "PD3"})
    assert [row["Ylamp"] for row in recording.rows] == [0, 0, 1, 1, 1]


def test_a_message_that_is_no_json_costs_that_message_only():
    async def run() -> dict:
        client = Client()
        client.send_text("{not json")
        return await client.request("initialize", {"processId": None, "rootUri": None, "capabilities": {}})

    assert "capabilities" in asyncio.run(run())["result"]


_START = """
import asyncio, json, sys
from lsp import worker_compile

mode, path = sys.argv[1:]
if mode == "record":
    known = worker_compile.record()
else:
    compiled = []
    inner = worker_compile._compile
    worker_compile._compile = lambda *args: (isinstance(args[0], str) and compiled.append(args[1])) or inner(*args)
    worker_compile.install(path)
from lsp.worker import connect

async def session():
    out = []
    send = connect(out.append)
    for message in [{"id": 1, "method": "initialize", "params": {"processId": None, "rootUri": None, "capabilities": {}}},
                    {"method": "initialized", "params": {}},
                    {"method": "textDocument/didOpen", "params": {"textDocument": {
                        "uri": "inmemory://a/lamp.ladder", "languageId": "ladder", "version": 1, "text": sys.stdin.read()}}}]:
        send(json.dumps({"jsonrpc": "2.0", **message}))
    await asyncio.sleep(0.2)
    return out

out = asyncio.run(session())
if mode == "record":
    worker_compile.stop()
    worker_compile.save(known, path)
    print(json.dumps({"out": out, "recorded": len(known)}))
else:
    print(json.dumps({"out": out, "compiled": compiled}))
"""


def test_the_start_runs_the_same_with_the_code_compiled_by_the_build(tmp_path):
    """lsp/worker_compile.py, as web/pyodide-files.mjs and web/src/server.js use it: the code
    recorded while one server starts answers every compile of the next start, which answers the
    same messages. Both with one hash seed: attrs writes a hash of a string into the `__hash__` it
    generates, so with another seed those (18, of attrs' own classes) are compiled again."""
    def start(mode: str) -> dict:
        done = subprocess.run([sys.executable, "-c", _START, mode, str(tmp_path / "start-code.marshal")],
                              input=env.LAMP_BAD, capture_output=True, text=True, timeout=120, cwd=env.REPO,
                              env={**os.environ, "PYTHONHASHSEED": "1"})
        assert done.returncode == 0, done.stderr[-3000:]
        return json.loads(done.stdout)

    recorded, answered = start("record"), start("install")
    assert recorded["recorded"] > 500  # lsprotocol's classes, each with its methods
    assert answered["compiled"] == [], answered["compiled"]
    assert answered["out"] == recorded["out"]
    assert any("LD102" in text for text in answered["out"])


def test_compiled_code_keeps_the_callers_future_flags(tmp_path):
    """compile() takes `from __future__` flags over from its caller: code recorded for a caller with
    `annotations` is not given to one without."""
    from lsp import worker_compile

    source = "def f(x: int) -> None: pass\n"
    plain: dict = {}
    later: dict = {}
    known = worker_compile.record()
    try:
        exec(compile("from __future__ import annotations\ncode = compile(source, 'gen', 'exec')", "a", "exec",
                     dont_inherit=True),
             {"source": source}, later)
    finally:
        worker_compile.stop()
    worker_compile.save(known, str(tmp_path / "code.marshal"))
    worker_compile.install(str(tmp_path / "code.marshal"))
    try:
        exec(compile("code = compile(source, 'gen', 'exec')", "b", "exec", dont_inherit=True), {"source": source}, plain)
    finally:
        worker_compile.stop()
    namespaces: list[dict] = [{}, {}]
    exec(later["code"], namespaces[0])
    exec(plain["code"], namespaces[1])
    assert namespaces[0]["f"].__annotations__ == {"x": "int", "return": "None"}
    assert namespaces[1]["f"].__annotations__ == {"x": int, "return": None}
