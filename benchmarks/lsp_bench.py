"""The language server's latency as an editor sees it: `python -m ladder lsp`
driven over stdio by a pytest-lsp client, with the shipped settings (the
adaptive `ladder.diagnosticsDelayMs`) unless `--delay-ms` sets the delay.

Measured on programs in the text form, a fresh server per run, twice over:

* at the wire (the targets): benchmarks/wiretap.py sits between client and
  server and notes when each message has crossed, so a time runs from the
  client's message sent to the server's answer arrived, as an editor would
  have it;
* in this Python client: until it has parsed the JSON (not converted it to
  lsprotocol objects, which would add 100+ ms to a big reply). A reply over
  `BIG_REPLY` bytes is not parsed at all (its result is taken as null; no
  measure looks into one): parsing the 13 MB outline of 18,000 rungs held
  this client 1.4 s and more, during which it sent nothing, so that the
  server saw a second of quiet (and collected its garbage) then a burst of
  the edits and requests due meanwhile, which an editor in Node, parsing it
  in a few tens of milliseconds, never sends. For the same reason the
  diagnostics a server publishes are read with `json.loads` for their
  document, version and codes only, not turned into lsprotocol objects
  (1,500 diagnostics held this client long enough to fall behind a storm).

The measures, with the targets of a 2,000-rung program:

* didOpen -> publishDiagnostics for version 1                target median <= 250 ms
* a one-character edit inside the first name of the middle rung (a new
  character, then the old one back), didChange -> publishDiagnostics
  for that version                                          target median <= 20 ms, p90 <= 40 ms
* a blank line added above the middle rung, then removed
  (every rung below moves)                                  target median <= 30 ms
* where the program has an I/O table, the same one-character edit in the
  name on its middle row                                    target median <= 20 ms, p90 <= 40 ms
* hover and completion on names, document unchanged        target median <= 10 ms
* typing: an edit every 100 ms and, at a random moment before the next, a
  completion where it was made or a hover on a name, in turn; each
  request's reply (an error reply, ContentModified, does not count)
* the storm: one one-character edit every 50 ms, and requests (hover,
  completion, documentSymbol, semanticTokens/full, ... whatever the server
  offers) at random moments in between; every reply       target: none later than 100 ms
  (a request still unanswered a few seconds after the storm counts as never answered)

The shapes (`--shape`, repeated to add more):

* generated: chain-timers-parallels (the realistic one: a contact, a timer
  and a coil per rung, each rung reading the relay the one before wrote,
  every fourth with a parallel branch), long-comments, wide-rungs (its own
  target: open <= 500 ms), io-table (a Modbus slave whose I/O table has a
  row per rung: 80 pins, the rest Modbus addresses), of `--rungs` rungs;
  chain-18000, the chain at 18,000 rungs (5.2 MB), whose targets are an edit
  (either kind) to its diagnostics <= 60 ms and hover or completion during
  typing <= 20 ms (no target for its open);
* corpus:<dialect>/<path>: each `.ld` file of the corpus beside the checkout
  (LDmicro0.1 and LDmicro0.2, which LDmicro 5.4 writes), converted and its
  rungs repeated up to `--rungs` with the names of the n-th copy ending in n
  (but for the names with a pin: every copy drives the original's pins).
  `corpus` runs every file, `corpus:GLOB` those whose name matches
  ('corpus:0.1/*', 'corpus:*blink*'); a file that fails to convert is listed
  as such. A byte-for-byte copy of a file is run once.
* all: every shape.

Figures pool all runs (median, p90, worst); per-run medians show the spread;
a table at the end gives one line per shape with the targets it misses. The
machine is small and shared: expect noise. `--profile DIR` runs the server
under cProfile (benchmarks/bench_server.py), one profile per phase, and
prints the project's functions that took the most time per event.

Run on demand: `python benchmarks/lsp_bench.py [--shape NAME|all|corpus|corpus:GLOB]...
[--rungs 2000] [--runs 3] [--edits 30] [--storm-seconds 30] [--delay-ms N] [--profile DIR] [--cpu]
[--baseline CHECKOUT]`:
a run of several corpus files does 10 edits and a 5 s storm a run for each
unless --edits and --storm-seconds say otherwise. `--cpu` starts no server:
it prints, for each shape, the CPU time the read and the check of each
version take in process (robust on a loaded machine, where the times at the
wire are not). `--baseline CHECKOUT` runs a second server from another
checkout (`git worktree add --detach ../base <commit>`), its runs alternated
with this checkout's on the same texts, so that the table has a before row
above each shape's row from one run of the machine."""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import fnmatch
import functools
import json
import os
import platform
import pstats
import random
import re
import signal
import statistics
import sys
import tempfile
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import shapes
from lsprotocol import types
from pygls.protocol import JsonRPCResponseMessage, LanguageServerProtocol
from pytest_lsp import client_capabilities, make_test_lsp_client

from lang.loader import TEXT_KIND, parse
from lang.model import Span
from lang.textform.details import NAME_KINDS
from lang.textform.writer import render_program

ROOT = Path(__file__).resolve().parents[1]
WIRETAP = Path(__file__).resolve().parent / "wiretap.py"
BENCH_SERVER = Path(__file__).resolve().parent / "bench_server.py"
TOO_LARGE = "lsp-too-large"  # the code of the server's one diagnostic on a document it does not analyse
URI = "file:///tmp/lsp-bench/bench.ladder"
DOC = types.TextDocumentIdentifier(uri=URI)
TYPED = "abcdefghijklmnopqrstuvwxyz"  # the characters typed over a name's last one
LATE_MS = 100
TYPING_MS = 100  # between two keystrokes while typing
# measure -> [(statistic, limit in ms)]: the targets for a 2,000-rung program
TARGETS = {"open": [("median", 250)], "1-character edit": [("median", 20), ("p90", 40)],
           "line added/removed": [("median", 30)], "I/O table edit": [("median", 20), ("p90", 40)],
           "hover": [("median", 10)], "completion": [("median", 10)],
           "hover during typing": [], "completion during typing": [], "storm replies": [("worst", LATE_MS)]}
WIDE_TARGETS = {**TARGETS, "open": [("median", 500)]}
BIG_TARGETS = {**TARGETS, "open": [], "1-character edit": [("median", 60)], "line added/removed": [("median", 60)],
               "hover during typing": [("median", 20)], "completion during typing": [("median", 20)]}
BIG_RUNGS = 18000
IDLE = re.compile(r"'(poll|select)' of 'select\.")  # the event loop waiting for input: not work
PUBLISHED = b'"textDocument/publishDiagnostics"'
BIG_REPLY = 1 << 18  # bytes of a reply's body over which this client does not parse it
REPLY_ID = re.compile(rb'"id":\s*("[^"]*"|-?\d+)')  # a reply's id, among the first or last bytes of its body


@dataclass(frozen=True)
class Shape:
    name: str
    text: Callable[[int], str]  # the program in the text form, for a number of rungs
    rungs: int | None = None  # its own size; None: --rungs
    targets: dict[str, list[tuple[str, float]]] = field(default_factory=lambda: TARGETS)
    corpus: bool = False


def generated(build: Callable[[int], str]) -> Callable[[int], str]:
    """A generated `.ld` program, read and written in the text form."""
    def text(rungs: int) -> str:
        program, problems = parse(build(rungs), "ld")
        assert not problems, problems
        return render_program(program)
    return text


GENERATED = [Shape("chain-timers-parallels", generated(shapes.chain_timers_parallels)),
             Shape("long-comments", generated(shapes.long_comments)),
             Shape("wide-rungs", generated(shapes.wide_rungs), targets=WIDE_TARGETS),
             Shape("io-table", generated(shapes.io_table)),
             Shape(f"chain-{BIG_RUNGS}", generated(shapes.chain_timers_parallels), BIG_RUNGS, BIG_TARGETS)]


def corpus_shapes(root: Path) -> tuple[list[Shape], list[tuple[str, str]]]:
    """A shape for each `.ld` file of the corpus, `corpus:<dialect>/<path>`,
    and a note for each file that is a byte-for-byte copy of one before it
    (run once), with the name of that one."""
    found: list[Shape] = []
    copies: list[tuple[str, str]] = []
    first_of: dict[bytes, str] = {}
    for path in sorted(root.rglob("*.ld")):
        name = f"corpus:{shapes.dialect(path)}/{path.relative_to(root)}"
        same = first_of.setdefault(path.read_bytes(), name)
        if same != name:
            copies.append((f"{name} is a copy of {same} (run once)", same))
            continue
        found.append(Shape(name, functools.partial(shapes.converted, path), corpus=True))
    return found, copies


def selected(patterns: list[str], corpus_folder: Path) -> tuple[list[Shape], list[str]]:
    """The shapes the --shape patterns name, in the order given, and the
    notes on the corpus's copies when it is part of them."""
    corpus, copies = corpus_shapes(corpus_folder)
    chosen: list[Shape] = []
    for pattern in patterns:
        if pattern == "all":
            matched = [*GENERATED, *corpus]
        elif pattern == "corpus":
            matched = corpus
        elif pattern.startswith("corpus:"):
            matched = [s for s in corpus if fnmatch.fnmatchcase(s.name, pattern)]
        else:
            matched = [s for s in GENERATED if s.name == pattern]
        if not matched:
            raise SystemExit(f"--shape {pattern}: no such shape (the shapes: {', '.join(s.name for s in GENERATED)}, "
                             f"all, corpus, corpus:GLOB over {', '.join(s.name for s in corpus[:2])}, ...)")
        chosen += [s for s in matched if s not in chosen]
    return chosen, [note for note, original in copies if original in {s.name for s in chosen}]


def position_params(cls):
    return lambda pos: cls(text_document=DOC, position=pos)


# the requests of the storm: name -> (method, server capability, params for a position)
REQUESTS = {
    "hover": (types.TEXT_DOCUMENT_HOVER, "hover_provider", position_params(types.HoverParams)),
    "completion": (types.TEXT_DOCUMENT_COMPLETION, "completion_provider", position_params(types.CompletionParams)),
    "definition": (types.TEXT_DOCUMENT_DEFINITION, "definition_provider", position_params(types.DefinitionParams)),
    "documentHighlight": (types.TEXT_DOCUMENT_DOCUMENT_HIGHLIGHT, "document_highlight_provider",
                          position_params(types.DocumentHighlightParams)),
    "documentSymbol": (types.TEXT_DOCUMENT_DOCUMENT_SYMBOL, "document_symbol_provider",
                       lambda pos: types.DocumentSymbolParams(text_document=DOC)),
    "foldingRange": (types.TEXT_DOCUMENT_FOLDING_RANGE, "folding_range_provider",
                     lambda pos: types.FoldingRangeParams(text_document=DOC)),
    "semanticTokens/full": (types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL, "semantic_tokens_provider",
                            lambda pos: types.SemanticTokensParams(text_document=DOC)),
}


def percentile(samples: list[float], q: float) -> float:
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def stats(samples: list[float]) -> dict[str, float]:
    return {"median": statistics.median(samples), "p90": percentile(samples, 0.9), "worst": max(samples)}


class Session:
    """One fresh server with the document open; times edits and requests."""

    def __init__(self, text: str, profile: Path | None = None, max_chars: int | None = None,
                 checkout: Path = ROOT):
        self.checkout = checkout  # whose code the server runs: `python -m ladder` imports from its cwd first
        self.lines = text.splitlines(keepends=True)
        self.client = make_test_lsp_client()
        self.version = 0
        self.profile = profile  # where the profiled server writes each phase's profile, or None
        self.max_chars = max_chars  # the server's size limit set to this, or None
        self.profiles: list[tuple[str, int, Path]] = []  # (measure, events, profile) of each phase profiled
        self.failed: set[str] = set()  # the ids of the requests answered with an error
        self.codes_at_open: list[str] = []
        self.measures: dict[int, str] = {}  # version -> the measure its diagnostics count in
        handle, self.tap_log = tempfile.mkstemp(prefix="lsp-bench-", suffix=".log")
        os.close(handle)
        self.published: dict[int, float] = {}  # version -> when its diagnostics arrived
        self.codes: dict[int, list[str]] = {}  # version -> the codes of its diagnostics (the reader keeps no more)
        self.waiters: dict[int, asyncio.Future] = {}
        self.client.protocol.fm._features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = self.on_diagnostics

    def on_diagnostics(self, params: types.PublishDiagnosticsParams) -> None:
        if params.uri != URI or params.version is None:
            return
        self.published[params.version] = time.perf_counter()
        if params.version == 1:
            self.codes_at_open = self.codes.get(1, [])
        future = self.waiters.pop(params.version, None)
        if future is not None and not future.done():
            future.set_result(None)

    async def start(self, delay_ms: int | None) -> set[str]:
        """Starts the server; the names of the REQUESTS it offers."""
        if delay_ms is not None:
            self.client.set_configuration({"diagnosticsDelayMs": delay_ms}, section="ladder")
        server = ["-m", "ladder", "lsp"]
        if self.profile is not None or self.max_chars is not None:
            server = [str(BENCH_SERVER), *(["--profile", str(self.profile)] if self.profile else []),
                      *(["--max-chars", str(self.max_chars)] if self.max_chars else [])]
        await self.client.start_io(sys.executable, str(WIRETAP), self.tap_log, sys.executable, *server, cwd=self.checkout)
        self.skip_big_replies()
        result = await self.client.initialize_session(
            types.InitializeParams(capabilities=client_capabilities("visual-studio-code")))
        await asyncio.sleep(0.3)  # the server pulls its settings
        # from here on replies stay plain JSON, as an editor reads them: turning a big one (the
        # documentSymbol of 2,000 rungs) into lsprotocol objects, or pygls's namedtuples, would cost
        # this client 100+ ms per reply that the server is not to blame for
        self.client.protocol.get_result_type = lambda method: None  # pygls's generic response,
        self.client.protocol._converter.register_structure_hook(   # with its result left as it is
            JsonRPCResponseMessage, lambda obj, cls: cls(**obj))
        return {name for name, (_, capability, _) in REQUESTS.items()
                if getattr(result.capabilities, capability, None)}

    def skip_big_replies(self) -> None:
        """The client's reader hands a reply over BIG_REPLY bytes on as
        `{"id": ..., "result": null}`: the time of every reply is taken at the
        wire, and parsing a big one would hold this client (not an editor)
        for seconds."""
        stream = self.client._server.stdout
        read = stream.readexactly

        async def readexactly(n: int) -> bytes:
            body = await read(n)
            head, tail = body[:200], body[-200:]
            if PUBLISHED in head:
                return self.light_diagnostics(body)
            if n <= BIG_REPLY or b'"method"' in head:
                return body
            found = REPLY_ID.search(head) or REPLY_ID.search(tail)
            return body if found is None else b'{"jsonrpc": "2.0", "id": %s, "result": null}' % found.group(1)

        stream.readexactly = readexactly

    def light_diagnostics(self, body: bytes) -> bytes:
        """A publishDiagnostics notification with its diagnostics taken out,
        their codes kept by version."""
        message = json.loads(body)
        params = message["params"]
        if params.get("uri") == URI and params.get("version") is not None:
            self.codes[params["version"]] = [str(d.get("code")) for d in params["diagnostics"]]
        params["diagnostics"] = []
        return json.dumps(message).encode()

    async def stop(self) -> None:
        """Shuts the server down; when a run failed, it may not answer: then
        the client ends it."""
        with contextlib.suppress(Exception):
            await asyncio.wait_for(self.client.shutdown_session(), 10)
        await self.client.stop()

    @contextlib.asynccontextmanager
    async def profiled(self, measure: str, events: int):
        """With --profile, the server profiles what it does inside (a signal
        to benchmarks/bench_server.py turns its profiler on, another off)."""
        if self.profile is None:
            yield
            return
        pid = int(Path(f"{self.profile}.pid").read_text())
        path = Path(f"{self.profile}.{len(self.profiles) + 1}")
        os.kill(pid, signal.SIGUSR1)
        await asyncio.sleep(0.1)  # the server takes the signal as it next wakes
        yield
        await asyncio.sleep(0.1)  # the work an edit leaves behind: its diagnostics are sent before it is done
        os.kill(pid, signal.SIGUSR2)
        while not path.exists():
            await asyncio.sleep(0.05)
        self.profiles.append((measure, events, path))

    def wire(self) -> dict[str, list[float]]:
        """The measures as the wire tap saw them: each timed version's didOpen
        or didChange to its publishDiagnostics, each timed request to its reply
        (a storm reply also under `storm <request>`)."""
        sent: dict[str, float] = {}
        arrived: dict[str, float] = {}
        with open(self.tap_log) as log:
            for line in log:
                at, direction, method, ident, version = line.rstrip("\n").split("\t")
                if method in ("textDocument/didOpen", "textDocument/didChange", "textDocument/publishDiagnostics"):
                    key = f"v{version}"
                elif ident != "-":
                    key = ident
                else:
                    continue
                (sent if direction == "c2s" else arrived).setdefault(key, float(at))
        os.unlink(self.tap_log)
        samples: dict[str, list[float]] = {}
        keys = [(f"v{version}", measure) for version, measure in self.measures.items()]
        keys += [(key, key.split(":")[0]) for key in sent if ":" in key]
        for key, measure in keys:
            if key in sent and key in arrived and measure != "untimed" and key not in self.failed:
                ms = (arrived[key] - sent[key]) * 1000
                samples.setdefault(measure, []).append(ms)
                if measure == "storm replies":
                    samples.setdefault("storm " + key.split(":")[1], []).append(ms)
        return samples

    async def until_diagnostics(self, sent: float) -> float:
        try:
            await asyncio.wait_for(self.waiters[self.version], 60)
        except TimeoutError:
            raise RuntimeError(f"no diagnostics for version {self.version} within 60 s") from None
        return (self.published[self.version] - sent) * 1000

    async def open(self) -> float:
        self.version = 1
        self.measures[1] = "open"
        self.waiters[1] = asyncio.get_running_loop().create_future()
        sent = time.perf_counter()
        self.client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=types.TextDocumentItem(
            uri=URI, language_id="ladder", version=1, text="".join(self.lines))))
        return await self.until_diagnostics(sent)

    def change(self, line: int, col: int, end_line: int, end_col: int, new: str, measure: str = "") -> float:
        """Sends one didChange (keeping `lines` in step); when it was sent."""
        self.version += 1
        if measure:
            self.measures[self.version] = measure
        self.waiters[self.version] = asyncio.get_running_loop().create_future()
        edited = "".join(self.lines[line:end_line + 1])
        cut = len("".join(self.lines[line:end_line])) + end_col
        self.lines[line:end_line + 1] = (edited[:col] + new + edited[cut:]).splitlines(keepends=True)
        sent = time.perf_counter()
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=self.version),
            content_changes=[types.TextDocumentContentChangePartial(
                range=types.Range(start=types.Position(line=line, character=col),
                                  end=types.Position(line=end_line, character=end_col)), text=new)]))
        return sent

    async def timed_change(self, measure: str, line: int, col: int, end_line: int, end_col: int, new: str) -> float:
        return await self.until_diagnostics(self.change(line, col, end_line, end_col, new, measure))

    async def request(self, name: str, position: types.Position, measure: str) -> float:
        """A request's time; its id names the measure it counts in at the wire
        (where an error reply does not count, but in the storm, where every
        reply does)."""
        method, _, params = REQUESTS[name]
        ident = f"{measure}:{name}:{uuid.uuid4()}"
        sent = time.perf_counter()
        try:
            # pygls's own send: pytest-lsp's checks of the reply against the capabilities are for tests
            await LanguageServerProtocol.send_request_async(self.client.protocol, method, params(position),
                                                            msg_id=ident)
        except Exception:
            if measure != "storm replies":
                self.failed.add(ident)
            raise
        return (time.perf_counter() - sent) * 1000


def drawn_names(lines: list[str]) -> list[tuple[int, Span]]:
    """(rung index, where it is drawn) of every name of the program, in rung
    order, as the reader found them (the names of a box sit inside it)."""
    program, _ = parse("".join(line if line.endswith("\n") else line + "\n" for line in lines), TEXT_KIND)
    return [(index, span) for index, element in program.elements() for f in element.spec.fields
            if f.kind in NAME_KINDS and (span := element.arg_spans.get(f.name)) is not None]


def middle_name(lines: list[str], rungs: int, drawn: list[tuple[int, Span]] | None = None) -> tuple[int, int]:
    """(line, column) of the last character of the first name drawn in the
    middle rung (or the next rung that has one)."""
    span = next((span for index, span in drawn or drawn_names(lines) if index >= rungs // 2), None)
    if span is None:
        raise ValueError("no name in the second half of the program")
    return span.line, span.end_col - 1


def table_row(lines: list[str]) -> tuple[int, int] | None:
    """(line, column) of the last character of the name on the middle row of
    the I/O table, or None when there is no table."""
    title = next((i for i, line in enumerate(lines) if line.startswith("I/O ASSIGNMENT:")), None)
    if title is None:
        return None
    rows = title + 3  # below the title, the column heads and the rule
    end = next((i for i in range(rows, len(lines)) if not lines[i].strip()), len(lines))
    if end == rows:
        return None
    middle = (rows + end) // 2
    name = lines[middle].split("|")[0].rstrip()
    return middle, len(name) - 1


def alternating(original: str) -> Callable[[int], str]:
    """The character typed by the n-th edit: a new one on even edits, the
    old one back on odd ones."""
    return lambda n: TYPED[(n // 2) % len(TYPED)] if n % 2 == 0 else original


async def one_run(text: str, rungs: int, edits: int, storm_seconds: float, delay_ms: int | None,
                  seed: int, profile: Path | None = None, max_chars: int | None = None,
                  checkout: Path = ROOT) -> tuple[dict[str, list[float]], dict]:
    session = Session(text, profile, max_chars, checkout)
    try:
        samples, extra = await measured(session, rungs, edits, storm_seconds, delay_ms, random.Random(seed))
    finally:
        await session.stop()
    return samples, {**extra, "wire": session.wire(), "codes at open": session.codes_at_open,
                     "profiles": session.profiles}


async def measured(session: Session, rungs: int, edits: int, storm_seconds: float, delay_ms: int | None,
                   rng: random.Random) -> tuple[dict[str, list[float]], dict]:
    offered = await session.start(delay_ms)
    async with session.profiled("open", 1):
        samples: dict[str, list[float]] = {"open": [await session.open()]}
    drawn = drawn_names(session.lines)
    line, col = middle_name(session.lines, rungs, drawn)
    typed = alternating(session.lines[line][col])
    async with session.profiled("1-character edit", edits):
        samples["1-character edit"] = [
            await session.timed_change("1-character edit", line, col, line, col + 1, typed(n)) for n in range(edits)]
    blank = session.lines[line - 1]  # the blank wire line above the names
    samples["line added/removed"] = []
    async with session.profiled("line added/removed", 2 * ((edits + 1) // 2)):
        for _ in range((edits + 1) // 2):
            samples["line added/removed"] += [
                await session.timed_change("line added/removed", line, 0, line, 0, blank),
                await session.timed_change("line added/removed", line, 0, line + 1, 0, "")]
    row = table_row(session.lines)
    if row is not None:
        row_line, row_col = row
        in_table = alternating(session.lines[row_line][row_col])
        async with session.profiled("I/O table edit", edits):
            samples["I/O table edit"] = [
                await session.timed_change("I/O table edit", row_line, row_col, row_line, row_col + 1, in_table(n))
                for n in range(edits)]

    names = [types.Position(line=span.line, character=span.col + 1) for _, span in drawn]
    for name in ("hover", "completion"):
        await session.request(name, names[0], "untimed")  # the first one builds the lazy helpers
        samples[name] = [await session.request(name, rng.choice(names), name) for _ in range(edits)]
    async with session.profiled("typing", edits):
        samples.update(await typing(session, names, line, col, typed, edits, rng))

    storm = {}
    if storm_seconds > 0:
        storm = await run_storm(session, sorted(offered), names, line, col, typed, storm_seconds, rng)
        samples["storm replies"] = [ms for _, ms in storm["replies"]]
    errors = [m.message.splitlines()[0] for m in session.client.log_messages if m.type == types.MessageType.Error]
    return samples, {**storm, "server errors": errors}


async def typing(session: Session, names: list[types.Position], line: int, col: int, typed: Callable[[int], str],
                 edits: int, rng: random.Random) -> dict[str, list[float]]:
    """Edits at the pace of typing, one every TYPING_MS, and after each, at
    a random moment before the next, a completion where the edit was made or
    a hover on a name, in turn: the time of each reply, but for those
    answered with an error (ContentModified: a later edit made it stale)."""
    samples: dict[str, list[float]] = {"hover during typing": [], "completion during typing": []}

    async def ask(name: str, position: types.Position) -> None:
        with contextlib.suppress(Exception):
            samples[f"{name} during typing"].append(await session.request(name, position, f"{name} during typing"))

    tasks = []
    start = time.perf_counter()
    for n in range(edits):
        session.change(line, col, line, col + 1, typed(n))
        await asyncio.sleep(rng.uniform(0, TYPING_MS / 2000))
        name, position = ("hover", rng.choice(names)) if n % 2 else ("completion", types.Position(line, col + 1))
        tasks.append(asyncio.create_task(ask(name, position)))
        await asyncio.sleep(max(0.0, start + (n + 1) * TYPING_MS / 1000 - time.perf_counter()))
    await asyncio.wait(tasks, timeout=60)
    final = session.waiters.get(session.version)  # gone once the last version's diagnostics came
    if final is not None:
        await asyncio.wait_for(final, 60)
    return samples


async def run_storm(session: Session, offered: list[str], names: list[types.Position], line: int, col: int,
                    typed, seconds: float, rng: random.Random) -> dict:
    """One edit every 50 ms, requests at random moments; every reply's time."""
    replies: list[tuple[str, float]] = []
    failed: list[str] = []

    async def ask(name: str) -> None:
        try:
            replies.append((name, await session.request(name, rng.choice(names), "storm replies")))
        except Exception as problem:  # an error reply is a reply, but one to report
            failed.append(f"{name}: {problem}")

    async def requests(until: float) -> None:
        while time.perf_counter() < until:
            await asyncio.sleep(rng.uniform(0, 0.1))
            tasks.append(asyncio.create_task(ask(rng.choice(offered))))

    tasks: list[asyncio.Task] = []
    first_version = session.version + 1
    start = time.perf_counter()
    asker = asyncio.create_task(requests(start + seconds))
    n = 0
    while time.perf_counter() < start + seconds:
        last_sent = session.change(line, col, line, col + 1, typed(n))
        n += 1
        await asyncio.sleep(max(0.0, start + n * 0.05 - time.perf_counter()))
    await asker
    settle = time.perf_counter() + 5  # then a request not answered counts as never answered
    final = session.waiters.get(session.version)
    while time.perf_counter() < settle and not (all(t.done() for t in tasks) and (final is None or final.done())):
        await asyncio.sleep(0.05)
    result = {"replies": list(replies), "sent": len(tasks), "failed": list(failed), "edits": n,
              "unanswered": len(tasks) - len(replies) - len(failed),
              "published": sum(1 for v in session.published if v >= first_version)}
    last = session.published.get(session.version)
    result["final diagnostics ms"] = None if last is None else (last - last_sent) * 1000
    # cancelling a request's future upsets the client when its reply comes: let the late ones finish
    await asyncio.wait(tasks, timeout=120)
    return result


def over(targets: dict[str, list[tuple[str, float]]], pooled: dict[str, dict[str, float]]) -> list[str]:
    """The targets a shape misses: `measure statistic figure>limit`."""
    return [f"{name} {stat} {pooled[name][stat]:.0f}>{limit:g}" for name, limits in targets.items()
            if name in pooled for stat, limit in limits if pooled[name][stat] > limit]


def report(name: str, runs: list[list[float]], limits: list[tuple[str, float]]) -> None:
    pooled = stats([ms for run in runs for ms in run])
    verdict = " ".join(f"{stat} <= {limit:g}" for stat, limit in limits) or "(none)"
    ok = "" if not limits else "ok" if all(pooled[stat] <= limit for stat, limit in limits) else "OVER"
    per_run = " ".join(f"{statistics.median(run):.1f}" for run in runs)
    print(f"    {name:24s} n={sum(map(len, runs)):4d}  median {pooled['median']:7.1f}  p90 {pooled['p90']:7.1f}  "
          f"worst {pooled['worst']:7.1f} ms   target {verdict:24s} {ok:4s}  per-run medians: {per_run}")


def report_all(all_samples: list[dict[str, list[float]]], targets: dict[str, list[tuple[str, float]]]) -> None:
    for name, limits in targets.items():
        if all(samples.get(name) for samples in all_samples):
            report(name, [samples[name] for samples in all_samples], limits)


def pooled_stats(all_samples: list[dict[str, list[float]]]) -> dict[str, dict[str, float]]:
    names = {name for samples in all_samples for name in samples}
    return {name: stats(pooled) for name in names if (pooled := [ms for s in all_samples for ms in s.get(name, [])])}


PROJECT = ("lang", "lsp", "ide", "compiler", "ladder")  # the folders whose functions a profile lists


def report_profile(measure: str, events: int, path: Path, top: int) -> None:
    """The project's functions that took the most time in the phase, by
    cumulative time per event (an edit, a request, the open), and by their
    own time."""
    table = pstats.Stats(str(path)).stats  # type: ignore[attr-defined]
    busy = sum(tt for (_, _, function), (_, _, tt, _, _) in table.items() if not IDLE.search(function))
    print(f"  server profile, {measure}: {events} event(s), {busy * 1000 / events:.1f} ms busy per event "
          f"(the profiler's overhead included; {path})")
    ours = [(ct, tt, nc, f"{Path(file).relative_to(ROOT)}:{line}:{function}")
            for (file, line, function), (_, nc, tt, ct, _) in table.items()
            if file.startswith(str(ROOT)) and Path(file).relative_to(ROOT).parts[0] in PROJECT]
    for title, order in (("cumulative", lambda f: f[0]), ("own time", lambda f: f[1])):
        print(f"    by {title}: cumulative ms/event, own ms/event, calls/event, function")
        for ct, tt, nc, where in sorted(ours, key=order, reverse=True)[:top]:
            print(f"    {ct * 1000 / events:10.2f} {tt * 1000 / events:10.2f} {nc / events:10.1f}   {where}")


@dataclass
class Row:
    """One shape's line of the table at the end: its figures at the wire."""
    shape: str
    rungs: int = 0
    megabytes: float = 0
    diagnostics: int = 0
    pooled: dict[str, dict[str, float]] = field(default_factory=dict)
    late: int = 0
    unanswered: int = 0
    missed: list[str] = field(default_factory=list)
    failure: str = ""


async def bench_shape(shape: Shape, args, many_corpus: bool) -> list[Row]:
    """The shape's row; with --baseline, the baseline's row first, their runs alternated."""
    rungs = shape.rungs or args.rungs
    edits = args.edits or (10 if many_corpus and shape.corpus else 30)
    storm_seconds = args.storm_seconds if args.storm_seconds is not None else 5 if many_corpus and shape.corpus else 30
    try:
        text = shape.text(rungs)
    except Exception as problem:  # a corpus file the converter cannot take: a row of the table, not the end of it
        print(f"\n{shape.name}: FAILED to convert: {type(problem).__name__}: {problem}")
        return [Row(shape.name, failure=f"FAILED to convert: {type(problem).__name__}: {problem}")]
    program, _ = parse(text, TEXT_KIND)
    delay = "shipped default (adaptive)" if args.delay_ms is None else f"{args.delay_ms} ms"
    limit = "" if args.max_chars is None else f", the server's size limit set to {args.max_chars} characters"
    megabytes = len(text.encode()) / 1e6
    checkouts = {shape.name: ROOT}
    if args.baseline is not None:
        checkouts = {f"{shape.name} [baseline]": args.baseline, shape.name: ROOT}
    print(f"\n{shape.name}: {len(text.splitlines())} lines, {megabytes:.2f} MB, {len(program.rungs)} rungs; "
          f"diagnosticsDelayMs {delay}{limit}, {args.runs} run(s) of {edits} edits, storm {storm_seconds:g} s"
          + (f"; runs alternated with the baseline's, {args.baseline}" if args.baseline else "")
          + (" (PROFILED: slower by the profiler's overhead)" if args.profile else ""))
    results: dict[str, list[tuple[dict[str, list[float]], dict]]] = {name: [] for name in checkouts}
    try:
        for seed in range(args.runs):
            for name, checkout in checkouts.items():
                stem = re.sub(r"[^\w.-]+", "_", name)  # the profiles' file names
                results[name].append(await one_run(
                    text, rungs, edits, storm_seconds, args.delay_ms, seed,
                    None if args.profile is None else args.profile / f"{stem}-{seed + 1}", args.max_chars, checkout))
    except Exception as problem:  # a server that stopped answering, a shape with no name to edit
        print(f"  FAILED: {type(problem).__name__}: {problem}")
        return [Row(name, len(program.rungs), megabytes, failure=f"FAILED during a run: {type(problem).__name__}: "
                    f"{problem}") for name in checkouts]
    print("  load average of the machine after the runs (1, 5, 15 min): " + ", ".join(f"{load:.1f}" for load in os.getloadavg())
          + f" on {os.cpu_count()} CPUs")
    return [shape_row(Row(name, len(program.rungs), megabytes), shape, runs, args, len(checkouts) > 1)
            for name, runs in results.items()]


def shape_row(row: Row, shape: Shape, results: list[tuple[dict[str, list[float]], dict]], args, named: bool) -> Row:
    """Prints the figures of one server's runs of a shape; its row."""
    if named:
        print(f" {row.shape}:")
    codes = results[0][1]["codes at open"]
    row.diagnostics = len(codes)
    print(f"  {row.diagnostics} diagnostics at open")
    if TOO_LARGE in codes:
        print(f"  NOT ANALYSED: the server does not read a document this large ({TOO_LARGE}); --max-chars lifts "
              "its limit")
        row.missed.append(f"NOT ANALYSED ({TOO_LARGE})")
    print("  at the wire (the targets):")
    report_all([extra["wire"] for _, extra in results], shape.targets)
    print(f"  in this Python client (its JSON parsing included, but of replies over {BIG_REPLY >> 10} KB):")
    report_all([samples for samples, _ in results], shape.targets)
    row.pooled = pooled_stats([extra["wire"] for _, extra in results])
    row.missed += over(shape.targets, row.pooled)
    for run, (_, extra) in enumerate(results, 1):
        if "replies" in extra:
            wire = extra["wire"].get("storm replies", [])
            late = [ms for ms in wire if ms > LATE_MS]
            row.late += len(late)
            row.unanswered += extra["unanswered"]
            final = extra["final diagnostics ms"]
            print(f"  storm run {run}: {extra['edits']} edits, {extra['sent']} requests: {len(late)} replies later than "
                  f"{LATE_MS} ms at the wire, worst {max(wire, default=0):.1f} ms "
                  f"(in this client {max((ms for _, ms in extra['replies']), default=0):.1f} ms), "
                  f"{extra['unanswered']} never answered, {len(extra['failed'])} error replies "
                  f"({'ok' if not late and not extra['unanswered'] else 'OVER'}); diagnostics for {extra['published']} "
                  "versions, the last " + ("never" if final is None else f"{final:.0f} ms after the last edit"))
            by_kind = {kind[len("storm "):]: ms for kind, ms in extra["wire"].items() if kind.startswith("storm ")}
            print("    at the wire: " + ", ".join(f"{kind} {statistics.median(v):.1f}/{max(v):.1f}"
                                              for kind, v in sorted(by_kind.items()) if kind != "replies")
                  + " ms (median/worst)")
            for failure in extra["failed"][:3]:
                print(f"    error reply: {failure}")
        for error in extra["server errors"][:3]:
            print(f"  run {run} server error: {error}")
    if row.unanswered:
        row.missed.append(f"storm: {row.unanswered} never answered")
    for measure, events, path in results[0][1]["profiles"]:
        report_profile(measure, events, path, args.profile_top)
    return row


COLUMNS = [("open", "median"), ("1-character edit", "median"), ("1-character edit", "p90"),
           ("line added/removed", "median"), ("I/O table edit", "median"), ("hover", "median"),
           ("completion", "median"), ("hover during typing", "median"), ("completion during typing", "median"),
           ("storm replies", "worst")]
HEADS = ["open", "edit", "edit90", "line", "table", "hover", "compl", "typ-hov", "typ-cmp", "storm"]


def print_table(rows: list[Row], notes: list[str]) -> None:
    """One line per shape: its medians (and the edit's p90, the storm's
    worst) at the wire in ms, pooled over the runs, and the targets missed."""
    width = max(len(row.shape) for row in rows)
    print("\nAt the wire, ms, pooled over the runs: medians, but edit90 (the 1-character edit's p90) and storm (the "
          "storm's worst reply; late: replies over 100 ms); typ-: during typing; the targets missed at the end")
    print(f"{'shape':{width}s} {'rungs':>6s} {'MB':>5s} {'diags':>6s} " + " ".join(f"{h:>7s}" for h in HEADS)
          + f" {'late':>5s}  verdict")
    for row in rows:
        if row.failure:
            print(f"{row.shape:{width}s} {row.failure}")
            continue
        figures = " ".join(f"{row.pooled[m][stat]:7.1f}" if m in row.pooled else f"{'-':>7s}" for m, stat in COLUMNS)
        print(f"{row.shape:{width}s} {row.rungs:6d} {row.megabytes:5.2f} {row.diagnostics:6d} {figures} {row.late:5d}  "
              + ("OVER: " + ", ".join(row.missed) if row.missed else "ok"))
    for note in notes:
        print(f"  {note}")


def cpu_shape(shape: Shape, rungs: int, runs: int, edits: int) -> None:
    """--cpu: the CPU time (`time.process_time`, which a loaded machine
    inflates far less than wall time) of what the server does for each
    measure, in this process, without the protocol: the read (with the
    editor's line hints) and the check of each version, a fresh reader and
    checker each run. The glyph tables are built first, as the server does
    when it starts."""
    from lang.textform.elements import prepare

    prepare()
    text = shape.text(rungs)
    samples: dict[str, list[float]] = {"open": [], "edit": [], "line": [], "table": []}
    for _ in range(runs):
        for measure, taken in cpu_run(text, rungs, edits).items():
            samples[measure] += taken
    figures = "  ".join(f"{measure} {statistics.median(taken):7.1f}" if taken else f"{measure} {'-':>7}"
                        for measure, taken in samples.items())
    print(f"{shape.name[:60]:60}  {figures}", flush=True)


def cpu_run(text: str, rungs: int, edits: int) -> dict[str, list[float]]:
    """One run of --cpu: the open, then the edits of lsp_bench's measures."""
    from ide.incremental import IncrementalReader
    from lang.checks import Checker
    from lsp.idle import IdleCollector
    from lsp.text import LineDocument

    document = LineDocument("file:///bench.ladder", text)
    reader, checker = IncrementalReader(TEXT_KIND), Checker()
    collector = IdleCollector()

    def analysed() -> float:
        start = time.process_time()
        # the server reads and checks with the collector held off (lsp/idle.py); left on, the
        # open's figure would be mostly full collections the server never makes
        with collector.reading():
            checker.check(reader.read(document.source, document.take_edited())[0], reader.moved)
        return (time.process_time() - start) * 1000

    def changed(line: int, col: int, end_line: int, end_col: int, new: str) -> float:
        document.apply_change(types.TextDocumentContentChangePartial(range=types.Range(
            start=types.Position(line=line, character=col),
            end=types.Position(line=end_line, character=end_col)), text=new))
        return analysed()

    samples: dict[str, list[float]] = {"open": [analysed()], "edit": [], "line": [], "table": []}
    lines = [line.rstrip("\n") for line in document.lines]
    line, col = middle_name(lines, rungs)
    typed = alternating(lines[line][col])
    samples["edit"] = [changed(line, col, line, col + 1, typed(n)) for n in range(edits)]
    blank = document.lines[line - 1]  # the blank wire line above the names, as the wire's measure adds
    for _ in range((edits + 1) // 2):
        samples["line"] += [changed(line, 0, line, 0, blank), changed(line, 0, line + 1, 0, "")]
    table = table_row(lines)
    if table is not None:
        row, at = table
        in_table = alternating(lines[row][at])
        samples["table"] = [changed(row, at, row, at + 1, in_table(n)) for n in range(edits)]
    return samples


def interpreter() -> str:
    """The Python the servers run on: the figures depend on its build. The
    README's venv takes Debian's python3, whose interpreter has libpython
    linked in; on one built with a shared libpython (pyenv's
    `--enable-shared`), the read and the check of `ctu_ctd_ctc_ctr`'s open
    took a fifth longer here (docs/lsp.md, "Speed")."""
    maps = Path("/proc/self/maps")
    shared = maps.exists() and "libpython" in maps.read_text()
    return (f"Python {platform.python_version()} ({os.path.realpath(sys.executable)}), libpython "
            + ("a shared library" if shared else "linked in"))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shape", action="append",
                        help="a shape's name, `all`, `corpus` (every .ld file of the corpus) or `corpus:GLOB` "
                             "over the corpus shapes' names, e.g. 'corpus:0.1/*' (a dialect), 'corpus:*blink*' "
                             "(one file); repeat to add more; default chain-timers-parallels")
    parser.add_argument("--rungs", type=int, default=2000, help="of the 2,000-rung shapes")
    parser.add_argument("--corpus", type=Path, default=shapes.corpus_root(),
                        help="the folder of LDmicro programs the corpus shapes come from (default: %(default)s)")
    parser.add_argument("--runs", type=int, default=None, help="fresh server each run (default 3; 1 with --profile)")
    parser.add_argument("--edits", "--rounds", type=int, default=None,
                        help="edits (and requests) timed per measure and run (default 30; 10 for each corpus file "
                             "when more than one is run); at least 20 over all runs")
    parser.add_argument("--storm-seconds", type=float, default=None,
                        help="0 skips the storm (default 30; 5 for each corpus file when more than one is run)")
    parser.add_argument("--delay-ms", type=int, default=None,
                        help="set ladder.diagnosticsDelayMs (default: not set, the shipped adaptive delay)")
    parser.add_argument("--profile", type=Path, default=None, metavar="DIR",
                        help="run the server under cProfile (benchmarks/bench_server.py), write each phase's "
                             "profile into DIR and print its top functions")
    parser.add_argument("--profile-top", type=int, default=15, help="functions printed per profile")
    parser.add_argument("--max-chars", type=int, default=None, metavar="N",
                        help="set the server's size limit (lsp.documents.MAX_CHARS, over which it does not analyse a "
                             "document) to N in the server's process, to see how it would fare on a bigger one")
    parser.add_argument("--baseline", type=Path, default=None, metavar="CHECKOUT",
                        help="also run the server of another checkout of this project (a git worktree of an "
                             "earlier commit), its runs alternated with this one's: a before/after table in one run")
    parser.add_argument("--cpu", action="store_true",
                        help="no server: the CPU time of the read and the check of each version in this process, "
                             "median ms of the open, the edit, the line added or removed and the I/O table edit")
    args = parser.parse_args()
    args.runs = args.runs or (1 if args.profile else 3)
    chosen, notes = selected(args.shape or ["chain-timers-parallels"], args.corpus)
    print(interpreter())
    if args.cpu:
        print(f"CPU ms in process, median of {args.runs} runs (open) and their edits")
        for shape in chosen:
            cpu_shape(shape, shape.rungs or args.rungs, args.runs, args.edits or 10)
        return
    many_corpus = sum(s.corpus for s in chosen) > 1
    if args.edits is not None and args.edits * args.runs < 20 and args.profile is None:
        parser.error("--edits times --runs must be at least 20 (but for a profile): a p90 of fewer is the worst")
    if args.profile is not None:
        args.profile.mkdir(parents=True, exist_ok=True)
    rows = [row for shape in chosen for row in asyncio.run(bench_shape(shape, args, many_corpus))]
    print_table(rows, notes)


if __name__ == "__main__":
    main()
