"""Fuzzing the language server over its real wire: random and mutated
JSON-RPC (every method it serves, params of the right shape and of every
wrong shape, positions far outside the document, frames with wrong lengths,
storms of edits) for a fixed time. Reports the messages sent, the requests
left without a reply (goal 0), server crashes (goal 0), and whether the
diagnostics of the document at the end equal `ladder check`'s. Inputs that
kill the server are saved under build/fuzz/lsp/. Run on demand:
`python benchmarks/fuzz_lsp.py [--seconds S] [--seed K] [--workers W]`."""

from __future__ import annotations

import json
import multiprocessing
import os
import queue
import random
import subprocess
import sys
import threading
import time

from fuzzing import ROOT, options  # sets sys.path for the imports below

# isort: split
from corpus import EXPORTS
from mutations import mutate

from lang.checks import check_program
from lang.loader import checkable, checked
from lang.textform.reader import read_text

URI = "file:///fuzz/program.ladder"
TEXTS = [path.read_text(encoding="cp1252") for path in sorted(EXPORTS.glob("*.txt"))[:8]]
POSITION_METHODS = ["textDocument/hover", "textDocument/completion", "textDocument/definition",
                    "textDocument/references", "textDocument/documentHighlight", "textDocument/prepareRename",
                    "textDocument/signatureHelp"]
DOCUMENT_METHODS = ["textDocument/documentSymbol", "textDocument/foldingRange", "textDocument/semanticTokens/full",
                    "textDocument/formatting", "textDocument/codeLens", "textDocument/inlayHint",
                    "textDocument/codeAction", "textDocument/rename", "workspace/executeCommand"]
JUNK = [None, [], [1, 2], {}, "x", -1, 2**31, 2**63, 1.5, True, {"line": -5}, "\udcff"]


class Session:
    def __init__(self):
        self.process = subprocess.Popen([sys.executable, "-m", "ladder", "lsp"], cwd=ROOT, stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        self.buffer, self.waiting, self.version, self.diagnostics = b"", set(), 1, {}
        self.next_id = 1
        self.swallowed = False
        # read the server's output all the time, or it blocks on a full pipe while we block writing
        self.chunks: queue.Queue[bytes] = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        while chunk := os.read(self.process.stdout.fileno(), 1 << 16):
            self.chunks.put(chunk)

    def send(self, message: dict, length_error: int = 0) -> None:
        body = json.dumps(message).encode("utf-8", errors="surrogatepass")
        self.process.stdin.write(b"Content-Length: %d\r\n\r\n" % (len(body) + length_error) + body)
        self.process.stdin.flush()

    def request(self, method: str, params, length_error: int = 0) -> None:
        ident, self.next_id = self.next_id, self.next_id + 1
        # a frame cut wrong gets no reply, nor does the next one when the long body swallowed its start
        if not length_error and not self.swallowed:
            self.waiting.add(ident)
        self.swallowed = length_error > 0
        self.send({"jsonrpc": "2.0", "id": ident, "method": method, "params": params}, length_error)

    def drain(self, seconds: float = 0.0) -> None:
        """Read the replies ready now, then for `seconds` more."""
        deadline = time.monotonic() + seconds
        while True:
            left = deadline - time.monotonic()
            try:
                self.buffer += self.chunks.get(timeout=left) if left > 0 else self.chunks.get_nowait()
            except queue.Empty:
                return
            while b"\r\n\r\n" in self.buffer:
                head, rest = self.buffer.split(b"\r\n\r\n", 1)
                size = int(next(ln for ln in head.split(b"\r\n") if ln.startswith(b"Content-Length")).split(b":")[1])
                if len(rest) < size:
                    break
                message, self.buffer = json.loads(rest[:size]), rest[size:]
                if "id" in message and "method" not in message:
                    self.waiting.discard(message["id"])
                elif message.get("method") == "textDocument/publishDiagnostics":
                    self.diagnostics[message["params"].get("version")] = message["params"]["diagnostics"]
            if time.monotonic() >= deadline:
                return


def _position(rng: random.Random):
    if rng.random() < 0.2:
        return rng.choice(JUNK)
    return {"line": rng.choice([0, 3, 7, 40, 10**6, -1]), "character": rng.choice([0, 5, 30, 10**6, -1])}


def _message(session: Session, rng: random.Random, text: str) -> str:
    kind = rng.random()
    doc = {"uri": URI}
    if kind < 0.35:  # an edit: the document's real text, changed the way a user (or a bad client) might
        session.version += 1
        lines = text.count("\n")
        start = {"line": rng.randrange(lines + 1), "character": rng.randrange(40)}
        change = {"range": {"start": start, "end": start}, "text": rng.choice(["X", "-", "] [", "\n", "", "||"])}
        if rng.random() < 0.1:
            change = {"text": mutate(text, rng, rng.randint(1, 5))}
        session.send({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
            "textDocument": {"uri": URI, "version": session.version}, "contentChanges": [change]}})
        return "didChange"
    if kind < 0.65:
        method = rng.choice(POSITION_METHODS)
        params = {"textDocument": doc, "position": _position(rng)}
        if rng.random() < 0.1:
            params = rng.choice(JUNK)
    else:
        method = rng.choice(DOCUMENT_METHODS)
        params = {"textDocument": doc, "options": {"tabSize": 4, "insertSpaces": True},
                  "range": {"start": _position(rng), "end": _position(rng)}, "newName": "Xnew",
                  "context": {"diagnostics": []}, "command": rng.choice(["ladder.build", "ladder.simulate", "x"]),
                  "arguments": [URI]}
        if rng.random() < 0.15:
            params = rng.choice(JUNK)
    session.request(method, params, length_error=rng.choice([0] * 30 + [-10, 3]))
    return method


def _worker(job):
    seed, seconds = job
    rng = random.Random(seed)
    sent = crashes = missing = 0
    session = _open(rng)
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        _message(session, rng, session.text)
        sent += 1
        session.drain()  # what is ready: the server must never block on a full pipe
        if session.process.poll() is not None:
            crashes += 1
            session = _open(rng)
    # the end: the document set to a known text, then its diagnostics against `ladder check`
    final = rng.choice(TEXTS)
    session.version += 1
    session.send({"jsonrpc": "2.0", "method": "textDocument/didChange", "params": {
        "textDocument": {"uri": URI, "version": session.version}, "contentChanges": [{"text": final}]}})
    while True:  # the server may still be working through a backlog: wait while replies come
        before = len(session.waiting)
        session.drain(10.0)
        if len(session.waiting) == before:
            break
    missing = len(session.waiting)
    program, problems = read_text(final)
    found = checked(program, check_program(program)) if checkable(program, problems) else []
    expected = sorted(d.code for d in problems + found)
    got = sorted(d.get("code") for d in session.diagnostics.get(session.version, []))
    session.process.kill()
    return sent, crashes, missing, expected == got


def _open(rng: random.Random) -> Session:
    session = Session()
    session.text = rng.choice(TEXTS)
    session.request("initialize", {"capabilities": {}})
    session.send({"jsonrpc": "2.0", "method": "initialized", "params": {}})
    session.send({"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": {
        "uri": URI, "languageId": "ladder", "version": 1, "text": session.text}}})
    return session


def main() -> int:
    args = options(__doc__, seconds=60)
    jobs = [(args.seed + k, args.seconds) for k in range(args.workers)]
    with multiprocessing.Pool(args.workers) as pool:
        results = pool.map(_worker, jobs)
    sent = sum(r[0] for r in results)
    crashes = sum(r[1] for r in results)
    missing = sum(r[2] for r in results)
    agree = all(r[3] for r in results)
    print(f"lsp: {sent} messages in {args.seconds:.0f} s, {missing} replies missing, {crashes} crashes, "
          f"diagnostics at the end {'equal' if agree else 'DIFFER from'} `ladder check`")
    return 0 if not crashes and not missing and agree else 1


if __name__ == "__main__":
    sys.exit(main())
