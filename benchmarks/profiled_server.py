"""The language server under cProfile, profiling only what it does between
two signals: `python benchmarks/profiled_server.py PREFIX` runs
`python -m ladder lsp` and writes its pid to PREFIX.pid; SIGUSR1 starts a
profile, SIGUSR2 ends it and writes it to PREFIX.1, PREFIX.2, ... in turn
(pstats files). lsp_bench.py --profile signals it around each phase (the
open, the edits of one kind, typing), so that a profile holds that phase's
work alone. The server does its work on its main thread, the one profiled."""

from __future__ import annotations

import cProfile
import os
import runpy
import signal
import sys
from pathlib import Path


def main() -> None:
    prefix = sys.argv[1]
    profiler = cProfile.Profile()
    written = 0

    def start(*_) -> None:
        profiler.clear()
        profiler.enable()

    def stop(*_) -> None:
        nonlocal written
        profiler.disable()
        written += 1
        path = Path(f"{prefix}.{written}")
        profiler.dump_stats(f"{path}.part")
        os.replace(f"{path}.part", path)  # whole when it appears

    signal.signal(signal.SIGUSR1, start)
    signal.signal(signal.SIGUSR2, stop)
    Path(f"{prefix}.pid").write_text(str(os.getpid()))
    sys.argv = ["ladder", "lsp"]
    runpy.run_module("ladder", run_name="__main__", alter_sys=True)


if __name__ == "__main__":
    main()
