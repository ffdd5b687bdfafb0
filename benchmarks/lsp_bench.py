"""The language server's latency as an editor sees it: `python -m ladder lsp`
driven over stdio by a pytest-lsp client, with the shipped settings (the
adaptive `ladder.diagnosticsDelayMs`) unless `--delay-ms` sets the delay.

Measured on a generated program in the text form (benchmarks/shapes.py read
with lang.loader.parse, written with render_program), a fresh server per run,
twice over:

* at the wire (the targets): benchmarks/wiretap.py sits between client and
  server and notes when each message has crossed, so a time runs from the
  client's message sent to the server's answer arrived, as an editor would
  have it;
* in this Python client: until it has parsed the JSON (not converted it to
  lsprotocol objects, which would add 100+ ms to a big reply). Parsing the
  1.4 MB outline of 2,000 rungs costs it about 35 ms, and every reply behind
  one waits that long too: an editor in Node parses it in a few.

* didOpen -> publishDiagnostics for version 1                target median <= 250 ms
* a one-character edit inside a name of the middle rung (a new character,
  then the old one back), didChange -> publishDiagnostics
  for that version                                          target median <= 20 ms, p90 <= 40 ms
* a blank line added above the middle rung, then removed
  (every rung below moves)                                  target median <= 30 ms
* hover and completion on names, document unchanged        target median <= 10 ms
* the storm: one one-character edit every 50 ms, and requests (hover,
  completion, documentSymbol, semanticTokens/full, ... whatever the server
  offers) at random moments in between; every reply       target: none later than 100 ms
  (a request still unanswered a few seconds after the storm counts as never answered)

Shapes: chain-timers-parallels (the realistic one: a contact, a timer and a
coil per rung, each rung reading the relay the one before wrote, every fourth
with a parallel branch), long-comments, wide-rungs. Figures pool all runs
(median, p90, worst); per-run medians show the spread. The machine is small
and shared: expect noise.

Run on demand: `python benchmarks/lsp_bench.py [--shape NAME|all] [--rungs 2000]
[--runs 3] [--edits 30] [--storm-seconds 30] [--delay-ms N]`."""

from __future__ import annotations

import argparse
import asyncio
import copy
import os
import random
import re
import statistics
import sys
import tempfile
import time
import uuid
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import shapes
from lsprotocol import types
from pygls.protocol import JsonRPCResponseMessage, LanguageServerProtocol
from pytest_lsp import client_capabilities, make_test_lsp_client

from lang.loader import TEXT_KIND, load_path, parse
from lang.textform.details import NAME_KINDS
from lang.textform.writer import render_program

ROOT = Path(__file__).resolve().parents[1]
WIRETAP = Path(__file__).resolve().parent / "wiretap.py"
URI = "file:///tmp/lsp-bench/bench.ladder"
DOC = types.TextDocumentIdentifier(uri=URI)
SHAPES = {"chain-timers-parallels": shapes.chain_timers_parallels, "long-comments": shapes.long_comments,
          "wide-rungs": shapes.wide_rungs}
# a real LDmicro program of each old dialect with timers (each timer has a DETAILS line once
# converted), from the corpus beside the checkout as the tests read it (tests/corpus.py)
CORPUS = ROOT.parent / "shared" / "corpus" / "ldmicro"
CONVERTED = {"converted-0.1": CORPUS / "reg" / "tests" / "timers-counters.ld",
             "converted-0.2": CORPUS / "Tests" / "test-uart.ld"}
IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
NAME = re.compile(r"\b[A-Z]\w*\d\b")  # the generated programs' names: R12, T5, TF7
TYPED = "abcdefghijklmnopqrstuvwxyz"  # the characters typed over a name's last one
LATE_MS = 100
# measure -> [(statistic, limit in ms)]
TARGETS = {"open": [("median", 250)], "1-character edit": [("median", 20), ("p90", 40)],
           "line added/removed": [("median", 30)], "hover": [("median", 10)], "completion": [("median", 10)],
           "storm replies": [("worst", LATE_MS)]}


def converted(path: Path, rungs: int) -> str:
    """The `.ld` file converted to the text form, its rungs repeated up to
    `rungs` with every name of the n-th copy ending in n (so DETAILS has a
    line per renamed timer, after the renamed rungs)."""
    program, problems = load_path(path)
    assert not problems, problems
    original = program.rungs
    program.rungs = []
    for copy_number in range(-(-rungs // len(original))):
        for rung in copy.deepcopy(original):
            for element in rung.elements():
                for f in element.spec.fields:
                    value = element.args.get(f.name)
                    if f.kind in NAME_KINDS and isinstance(value, str) and IDENTIFIER.fullmatch(value):
                        element.args[f.name] = f"{value}{copy_number}"
            program.rungs.append(rung)
    del program.rungs[rungs:]
    return render_program(program)


def shape_text(shape: str, rungs: int) -> str:
    if shape in CONVERTED:
        return converted(CONVERTED[shape], rungs)
    program, problems = parse(SHAPES[shape](rungs), "ld")
    assert not problems, problems
    return render_program(program)


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

    def __init__(self, text: str):
        self.lines = text.splitlines(keepends=True)
        self.client = make_test_lsp_client()
        self.version = 0
        self.measures: dict[int, str] = {}  # version -> the measure its diagnostics count in
        handle, self.tap_log = tempfile.mkstemp(prefix="lsp-bench-", suffix=".log")
        os.close(handle)
        self.published: dict[int, float] = {}  # version -> when its diagnostics arrived
        self.waiters: dict[int, asyncio.Future] = {}
        self.client.protocol.fm._features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = self.on_diagnostics

    def on_diagnostics(self, params: types.PublishDiagnosticsParams) -> None:
        if params.uri != URI or params.version is None:
            return
        self.published[params.version] = time.perf_counter()
        future = self.waiters.pop(params.version, None)
        if future is not None and not future.done():
            future.set_result(None)

    async def start(self, delay_ms: int | None) -> set[str]:
        """Starts the server; the names of the REQUESTS it offers."""
        if delay_ms is not None:
            self.client.set_configuration({"diagnosticsDelayMs": delay_ms}, section="ladder")
        await self.client.start_io(sys.executable, str(WIRETAP), self.tap_log, sys.executable, "-m", "ladder", "lsp",
                                   cwd=ROOT)
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

    async def stop(self) -> None:
        await self.client.shutdown_session()
        await self.client.stop()

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
            if key in sent and key in arrived and measure != "untimed":
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
        """A request's time; its id names the measure it counts in at the wire."""
        method, _, params = REQUESTS[name]
        sent = time.perf_counter()
        # pygls's own send: pytest-lsp's checks of the reply against the capabilities are for tests
        await LanguageServerProtocol.send_request_async(self.client.protocol, method, params(position),
                                                        msg_id=f"{measure}:{name}:{uuid.uuid4()}")
        return (time.perf_counter() - sent) * 1000


def middle_name(lines: list[str], rungs: int) -> tuple[int, int]:
    """(line, column) of the last character of the first name drawn above the
    middle rung (or the next rung that has one)."""
    for rung in range(rungs // 2 + 1, rungs + 1):
        numbered = next(i for i, line in enumerate(lines) if line.startswith(f"{rung:04d}|"))
        found = NAME.search(lines[numbered - 1])
        if found:
            return numbered - 1, found.end() - 1
    raise ValueError("no name in the second half of the program")


async def one_run(text: str, rungs: int, edits: int, storm_seconds: float, delay_ms: int | None,
                  seed: int) -> tuple[dict[str, list[float]], dict]:
    session = Session(text)
    offered = await session.start(delay_ms)
    rng = random.Random(seed)
    samples: dict[str, list[float]] = {"open": [await session.open()]}
    line, col = middle_name(session.lines, rungs)
    original = session.lines[line][col]

    def typed(n: int) -> str:  # a new character on even edits, the old one back on odd ones
        return TYPED[(n // 2) % len(TYPED)] if n % 2 == 0 else original

    samples["1-character edit"] = [await session.timed_change("1-character edit", line, col, line, col + 1, typed(n))
                                   for n in range(edits)]
    blank = session.lines[line - 1]  # the blank wire line above the names
    samples["line added/removed"] = []
    for _ in range((edits + 1) // 2):
        samples["line added/removed"].append(await session.timed_change("line added/removed", line, 0, line, 0, blank))
        samples["line added/removed"].append(await session.timed_change("line added/removed", line, 0, line + 1, 0, ""))

    names = [types.Position(line=i, character=m.start() + 1) for i, text_line in enumerate(session.lines)
             if text_line.startswith("    |") for m in NAME.finditer(text_line)]
    for name in ("hover", "completion"):
        await session.request(name, names[0], "untimed")  # the first one builds the lazy helpers
        samples[name] = [await session.request(name, rng.choice(names), name) for _ in range(edits)]

    storm = {}
    if storm_seconds > 0:
        storm = await run_storm(session, sorted(offered), names, line, col, typed, storm_seconds, rng)
        samples["storm replies"] = [ms for _, ms in storm["replies"]]
    errors = [m.message.splitlines()[0] for m in session.client.log_messages if m.type == types.MessageType.Error]
    await session.stop()
    return samples, {**storm, "server errors": errors, "wire": session.wire()}


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


def report(name: str, runs: list[list[float]]) -> None:
    pooled = stats([ms for run in runs for ms in run])
    verdict = " ".join(f"{stat} <= {limit}" for stat, limit in TARGETS[name])
    ok = all(pooled[stat] <= limit for stat, limit in TARGETS[name])
    per_run = " ".join(f"{statistics.median(run):.1f}" for run in runs)
    print(f"    {name:20s} n={sum(map(len, runs)):4d}  median {pooled['median']:7.1f}  p90 {pooled['p90']:7.1f}  "
          f"worst {pooled['worst']:7.1f} ms   target {verdict:24s} {'ok' if ok else 'OVER':4s}  per-run medians: {per_run}")


def report_all(all_samples: list[dict[str, list[float]]]) -> None:
    for name in TARGETS:
        if all(name in samples for samples in all_samples):
            report(name, [samples[name] for samples in all_samples])


async def bench_shape(shape: str, args) -> None:
    text = shape_text(shape, args.rungs)
    program, _ = parse(text, TEXT_KIND)
    delay = "shipped default (adaptive)" if args.delay_ms is None else f"{args.delay_ms} ms"
    print(f"\n{shape}: {len(text.splitlines())} lines, {len(text.encode()) / 1e6:.2f} MB, {len(program.rungs)} rungs; "
          f"diagnosticsDelayMs {delay}, {args.runs} run(s) of {args.edits} edits, storm {args.storm_seconds:g} s")
    results = [await one_run(text, args.rungs, args.edits, args.storm_seconds, args.delay_ms, seed)
               for seed in range(args.runs)]
    print("  at the wire (the targets):")
    report_all([extra["wire"] for _, extra in results])
    print("  in this Python client (its JSON parsing included):")
    report_all([samples for samples, _ in results])
    for run, (_, extra) in enumerate(results, 1):
        if "replies" in extra:
            wire = extra["wire"].get("storm replies", [])
            late = [ms for ms in wire if ms > LATE_MS]
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shape", choices=[*SHAPES, *CONVERTED, "all"], default="chain-timers-parallels")
    parser.add_argument("--rungs", type=int, default=2000)
    parser.add_argument("--runs", type=int, default=3, help="fresh server each run")
    parser.add_argument("--edits", "--rounds", type=int, default=30, help="edits (and requests) timed per measure, >= 30")
    parser.add_argument("--storm-seconds", type=float, default=30, help="0 skips the storm")
    parser.add_argument("--delay-ms", type=int, default=None,
                        help="set ladder.diagnosticsDelayMs (default: not set, the shipped adaptive delay)")
    args = parser.parse_args()
    if args.edits < 30:
        parser.error("--edits must be at least 30")
    for shape in [*SHAPES, *CONVERTED] if args.shape == "all" else [args.shape]:
        asyncio.run(bench_shape(shape, args))


if __name__ == "__main__":
    main()
