"""The language server's latency, measured from the client side over stdio
(what an editor sees), on the 2,000-rung program of parse_bench.py:

* didChange (a one-character edit inside one rung) -> publishDiagnostics
  for that version, with `ladder.diagnosticsDelayMs` = 0 (no debounce), or with
  the shipped settings (`--defaults`: the adaptive delay);
  also for an edit that adds a line (every rung below moves);
* hover on a name, and completion of a name, on the unchanged document.

Targets: diagnostics < 50 ms, hover and completion < 20 ms (medians).
Run on demand: `python benchmarks/lsp_bench.py [--rounds N]`. The machine is
small and shared, so the script prints medians and the 90th percentile."""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from lsprotocol import types  # noqa: E402
from parse_bench import big_program  # noqa: E402
from pytest_lsp import client_capabilities, make_test_lsp_client  # noqa: E402

from lang.textform.writer import render_program  # noqa: E402

URI = "file:///tmp/lsp-bench/big.ladder"


def percentile(samples: list[float], q: float) -> float:
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def report(name: str, samples: list[float], target: float) -> None:
    median = statistics.median(samples)
    flag = "ok" if median < target else "OVER"
    print(f"{name:48s} median {median:7.1f} ms   p90 {percentile(samples, 0.9):7.1f} ms   "
          f"(target < {target:.0f} ms) {flag}")


async def main(rounds: int, defaults: bool = False) -> None:
    client = make_test_lsp_client()
    published: dict[int, float] = {}
    waiters: dict[int, asyncio.Future] = {}

    def on_diagnostics(params: types.PublishDiagnosticsParams):
        if params.uri != URI:
            return
        published[params.version] = time.perf_counter()
        future = waiters.pop(params.version, None)
        if future is not None and not future.done():
            future.set_result(params)

    client.protocol.fm._features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = on_diagnostics
    if not defaults:
        client.set_configuration({"diagnosticsDelayMs": 0}, section="ladder")
    await client.start_io(sys.executable, "-m", "ladder", "lsp")
    await client.initialize_session(types.InitializeParams(capabilities=client_capabilities("visual-studio-code")))
    await asyncio.sleep(0.3)

    text = render_program(big_program())
    lines = text.splitlines(keepends=True)
    print(f"document: {len(lines)} lines, {len(text) / 1e6:.2f} MB, 2000 rungs")
    loop = asyncio.get_running_loop()
    version = 1
    waiters[1] = loop.create_future()
    start = time.perf_counter()
    client.text_document_did_open(types.DidOpenTextDocumentParams(
        text_document=types.TextDocumentItem(uri=URI, language_id="ladder", version=1, text=text)))
    await asyncio.wait_for(waiters.get(1) or asyncio.sleep(0), 60)
    print(f"didOpen -> diagnostics (cold read and check):  {(published[1] - start) * 1000:7.1f} ms")

    async def change(line: int, col: int, end_line: int, end_col: int, new: str) -> float:
        nonlocal version
        version += 1
        future = waiters[version] = loop.create_future()
        sent = time.perf_counter()
        client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=version),
            content_changes=[types.TextDocumentContentChangePartial(
                range=types.Range(start=types.Position(line=line, character=col),
                                  end=types.Position(line=end_line, character=end_col)), text=new)]))
        await asyncio.wait_for(future, 30)
        return (published[version] - sent) * 1000

    # a one-character edit in the middle of a name (rung 1001), back and forth
    target = next(i for i, line in enumerate(lines) if line.startswith("1001|")) - 1
    col = lines[target].index("Rm1000") + 3
    samples = []
    for n in range(rounds):
        samples.append(await change(target, col, target, col + 1, "1" if n % 2 == 0 else "0"))
    report("didChange (1 character) -> diagnostics", samples, 50)

    # a new line inside rung 1001 and its removal: 1,000 rungs move
    samples = []
    for _n in range(max(4, rounds // 4)):
        blank = lines[target + 2]
        samples.append(await change(target + 2, 0, target + 2, 0, blank))
        samples.append(await change(target + 2, 0, target + 3, 0, ""))
    report("didChange (a line added or removed) -> diagnostics", samples, 50)

    # hover on a name, completion of a name (document unchanged in between)
    position = types.Position(line=target, character=col)
    await client.text_document_hover_async(types.HoverParams(
        text_document=types.TextDocumentIdentifier(uri=URI), position=position))
    samples = []
    for _ in range(rounds):
        sent = time.perf_counter()
        result = await client.text_document_hover_async(types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=URI), position=position))
        samples.append((time.perf_counter() - sent) * 1000)
    assert result is not None
    report("hover on a name", samples, 20)

    samples = []
    for _ in range(rounds):
        sent = time.perf_counter()
        result = await client.text_document_completion_async(types.CompletionParams(
            text_document=types.TextDocumentIdentifier(uri=URI), position=position))
        samples.append((time.perf_counter() - sent) * 1000)
    report("completion of a name", samples, 20)
    items = result.items if hasattr(result, "items") else (result or [])
    print(f"  ({len(items)} completion items)")

    await client.shutdown_session()
    await client.stop()


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--defaults", action="store_true",
                        help="the shipped settings (adaptive diagnostics delay) instead of no debounce")
    args = parser.parse_args()
    asyncio.run(main(args.rounds, args.defaults))
