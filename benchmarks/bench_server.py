"""The language server as lsp_bench.py runs it when asked to look inside:
`python benchmarks/bench_server.py [--profile PREFIX] [--max-chars N]` runs
`python -m ladder lsp`, and

* with --profile, under cProfile, profiling only what the server does
  between two signals: it writes its pid to PREFIX.pid; SIGUSR1 starts a
  profile, SIGUSR2 ends it and writes it to PREFIX.1, PREFIX.2, ... in turn
  (pstats files). lsp_bench.py signals it around each phase (the open, the
  edits of one kind, typing), so that a profile holds that phase's work
  alone. The server does its work on its main thread, the one profiled.
* with --max-chars, with the size above which the server does not analyse
  a document (lsp.documents.MAX_CHARS) set to N in this process, no code
  changed: how the server would fare on a document over its limit."""

from __future__ import annotations

import argparse
import cProfile
import os
import runpy
import signal
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def profile_between_signals(prefix: str) -> None:
    profiler = cProfile.Profile()
    written = 0

    def start(*_) -> None:
        profiler.clear()
        profiler.enable()

    def stop(*_) -> None:
        nonlocal written
        profiler.disable()
        written += 1
        path = f"{prefix}.{written}"
        profiler.dump_stats(f"{path}.part")
        os.replace(f"{path}.part", path)  # whole when it appears

    signal.signal(signal.SIGUSR1, start)
    signal.signal(signal.SIGUSR2, stop)
    Path(f"{prefix}.pid").write_text(str(os.getpid()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--profile", metavar="PREFIX")
    parser.add_argument("--max-chars", type=int)
    args = parser.parse_args()
    if args.profile:
        profile_between_signals(args.profile)
    if args.max_chars:
        import lsp.documents

        lsp.documents.MAX_CHARS = args.max_chars
    sys.argv = ["ladder", "lsp"]
    runpy.run_module("ladder", run_name="__main__", alter_sys=True)


if __name__ == "__main__":
    main()
