"""The wire itself, byte for byte against the real server process: every
request gets an answer (InvalidParams when its params do not fit the
method), and a frame with a wrong Content-Length costs that one message, not
the connection."""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
URI = "file:///tmp/wire.ladder"
INVALID_PARAMS, INVALID_REQUEST = -32602, -32600


class Wire:
    def __init__(self):
        self.process = subprocess.Popen([sys.executable, "-m", "ladder", "lsp"], cwd=ROOT,
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        self.pending = b""

    def send(self, message: dict | bytes, short: int = 0) -> None:
        body = message if isinstance(message, bytes) else json.dumps(message).encode()
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % (len(body) - short) + body)
        self.process.stdin.flush()

    def request(self, ident: int, method: str, params, short: int = 0) -> None:
        self.send({"jsonrpc": "2.0", "id": ident, "method": method, "params": params}, short)

    def answers(self, wanted: set, seconds: float = 20) -> dict:
        """id -> the error code, or "result", of the replies until every wanted id came."""
        found: dict = {}
        deadline = time.monotonic() + seconds
        while not wanted <= set(found) and time.monotonic() < deadline:
            if select.select([self.process.stdout], [], [], 0.1)[0]:
                self.pending += os.read(self.process.stdout.fileno(), 1 << 16)
            while b"\r\n\r\n" in self.pending:
                head, rest = self.pending.split(b"\r\n\r\n", 1)
                size = int(next(line for line in head.split(b"\r\n") if line.startswith(b"Content-Length")).split(b":")[1])
                if len(rest) < size:
                    break
                reply, self.pending = json.loads(rest[:size]), rest[size:]
                if "id" in reply and "method" not in reply:
                    found[reply["id"]] = reply["error"]["code"] if "error" in reply else "result"
        return found

    def close(self) -> None:
        self.process.kill()
        self.process.wait()


@pytest.fixture
def wire():
    wire = Wire()
    wire.request(0, "initialize", {"capabilities": {}})
    wire.send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
    wire.send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": URI, "languageId": "ladder", "version": 1, "text": "LDmicro export text.\n"}}})
    assert wire.answers({0}) == {0: "result"}
    yield wire
    wire.close()


def test_every_request_with_params_that_do_not_fit_is_answered(wire):
    doc = {"uri": URI}
    wrong = {
        1: ("textDocument/hover", {"textDocument": doc}),  # no position
        2: ("textDocument/hover", None),
        3: ("textDocument/hover", [1, 2]),
        4: ("textDocument/hover", {"textDocument": doc, "position": {"line": -1, "character": 0}}),
        5: ("textDocument/hover", {"textDocument": doc, "position": {"line": 2**31, "character": 2**31}}),
        6: ("textDocument/formatting", {"textDocument": doc}),  # no options
        7: ("textDocument/completion", {}),
        8: ("textDocument/definition", {"textDocument": doc, "position": {"line": "a", "character": 0}}),
    }
    for ident, (method, params) in wrong.items():
        wire.request(ident, method, params)
    wire.send({"id": 9, "method": "textDocument/hover", "params": {}})  # no "jsonrpc": not a message
    assert wire.answers(set(wrong) | {9}) == {**{i: INVALID_PARAMS for i in wrong}, 9: INVALID_REQUEST}
    wire.request(10, "textDocument/hover", {"textDocument": doc, "position": {"line": 0, "character": 0}})
    assert wire.answers({10}) == {10: "result"}


@pytest.mark.parametrize("short", [10, 1, -3])
def test_a_frame_of_the_wrong_length_costs_only_itself(wire, short):
    position = {"textDocument": {"uri": URI}, "position": {"line": 0, "character": 0}}
    if short < 0:
        # too long: the body takes the start of the next frame, which is lost with it
        wire.request(1, "textDocument/hover", position, short)
        wire.request(2, "textDocument/hover", position)
        wire.request(3, "textDocument/hover", position)
        assert wire.answers({3}) == {3: "result"}
    else:
        wire.request(1, "textDocument/hover", position, short)
        wire.request(2, "textDocument/hover", position)
        assert wire.answers({2}) == {2: "result"}
    wire.send(b"{not json at all")
    wire.request(4, "textDocument/hover", position)
    assert wire.answers({4}) == {4: "result"}


@pytest.mark.parametrize("stdin", ["devnull", "file"])
def test_input_that_is_not_a_pipe_is_read_to_its_end(tmp_path, stdin):
    """`ladder lsp < /dev/null` (a service manager, a script) ends at once,
    without a traceback: the event loop cannot watch /dev/null, so the
    server reads it as it reads a file."""
    source = tmp_path / "input"
    source.write_bytes(b"")
    with open(os.devnull if stdin == "devnull" else source, "rb") as given:
        done = subprocess.run([sys.executable, "-m", "ladder", "lsp"], cwd=ROOT, stdin=given,
                              capture_output=True, timeout=30)
    assert done.returncode == 0
    assert b"Traceback" not in done.stderr


def test_shutdown_while_a_request_is_pending_is_answered_and_the_server_exits(wire):
    """pygls cancels the pending requests while iterating over the table their
    cancellation removes them from: the shutdown must still be answered."""
    text = (ROOT / "examples" / "reversing-motor.ladder").read_text(encoding="utf-8")
    wire.send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": "file:///tmp/motor.ladder", "languageId": "ladder", "version": 1, "text": text}}})
    wire.request(1, "workspace/executeCommand", {"command": "ladder.verify", "arguments": [
        "file:///tmp/motor.ladder", {"bound": 5000, "timeoutS": 30}]})
    wire.request(2, "shutdown", None)  # while the prover works (a proof takes ~0.3 s)
    assert wire.answers({2}).get(2) == "result"
    wire.send({"jsonrpc": "2.0", "method": "exit"})
    assert wire.process.wait(timeout=10) == 0


def test_the_server_goes_on_while_the_client_has_not_read_a_big_answer():
    """A big answer is written by a thread of its own: handing over answers
    larger than the pipe (the outline of 18,000 rungs is 13 MB) returns at
    once while the client reads nothing, the client then reads every answer
    whole and in order, and a client that has gone costs the server nothing
    but the answers dropped."""
    from lsp.transport import PipeWriter

    read_end, write_end = os.pipe()
    writer = PipeWriter(os.fdopen(write_end, "wb"))
    # 9 MB, the pipe holds 1 MB at most; a small answer after them waits its turn
    answers = [bytes([65 + n]) * (3 << 20) for n in range(3)] + [b"small"]
    start = time.monotonic()
    for answer in answers:
        writer.write(answer)
    assert time.monotonic() - start < 0.5
    received = bytearray()
    with os.fdopen(read_end, "rb") as reader:
        while len(received) < sum(map(len, answers)):
            received += reader.read1(1 << 20)
        writer.close()
        assert bytes(received) == b"".join(answers) and reader.read() == b""

    read_end, write_end = os.pipe()
    writer = PipeWriter(os.fdopen(write_end, "wb"))
    os.close(read_end)  # the client is gone
    writer.write(b"x" * (1 << 20))
    writer.write(b"y")
    writer.close()
