"""How `ladder build` and `ladder sim` grow with the program, on programs of
realistic shape (benchmarks/shapes.py): build time at 2,000 to 16,000 rungs
(past about 5,000 rungs no AVR has the flash, so the larger builds end at
LD703 after compiling everything) and the simulator's peak memory at 5,000
and 35,000 rungs (`/usr/bin/time -v`'s maximum resident set), next to that of
reading the file alone, which `ladder sim` cannot go below. Run on demand:
`python benchmarks/scale_bench.py [--quick]`. Targets: 16,000 rungs at most
2.2x the time of 8,000; the simulation of 35,000 at most 4x the memory of 5,000
and at most 500 MB."""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from shapes import chain_timers_parallels

ROOT = Path(__file__).resolve().parents[1]
READ_ONLY = "import sys; from lang.loader import load_path; load_path(sys.argv[1])"


def _run(argv: list[str]) -> tuple[float, int]:
    return _python(["-m", "ladder", *argv])


def _python(argv: list[str]) -> tuple[float, int]:
    """Wall seconds and peak resident kilobytes of `python ARGV`."""
    started = time.perf_counter()
    result = subprocess.run(["/usr/bin/time", "-v", sys.executable, *argv], cwd=ROOT,
                            capture_output=True, text=True)
    seconds = time.perf_counter() - started
    peak = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", result.stderr).group(1))
    return seconds, peak


def main() -> int:
    quick = "--quick" in sys.argv
    builds = (1000, 2000) if quick else (2000, 4000, 8000, 16000)
    sims = (1000, 7000) if quick else (5000, 35000)
    with tempfile.TemporaryDirectory() as folder:
        times = {}
        for rungs in builds:
            source = Path(folder) / f"b{rungs}.ld"
            source.write_text(chain_timers_parallels(rungs), encoding="ascii")
            times[rungs], _ = _run(["build", str(source), "-o", str(Path(folder) / "out.hex")])
            print(f"build {rungs:6d} rungs: {times[rungs]:7.1f} s")
        for small, large in zip(builds, builds[1:]):
            print(f"  {large} / {small}: {times[large] / times[small]:.2f}x (target <= 2.2x)")
        peaks = {}
        for rungs in sims:
            source = Path(folder) / f"s{rungs}.ld"
            source.write_text(chain_timers_parallels(rungs), encoding="ascii")
            _, peaks[rungs] = _run(["sim", str(source), "--for", "1s", "--watch", "Xstart"])
            _, read = _python(["-c", READ_ONLY, str(source)])
            print(f"sim {rungs:6d} rungs: {peaks[rungs] / 1024:7.0f} MB peak (reading the file alone: "
                  f"{read / 1024:.0f} MB)")
        small, large = sims
        print(f"  {large} / {small}: {peaks[large] / peaks[small]:.2f}x (target <= 4x, and <= 500 MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
