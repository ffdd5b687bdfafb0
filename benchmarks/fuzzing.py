"""What the fuzzers share: their options (`--seconds`, `--seed`, `--workers`,
`--inputs`), a pool of workers each drawing inputs from its own seed until the
time or the count is up, and the crashes saved under `build/fuzz/<name>/` for
replay. A fuzzer supplies `make(rng) -> input` and `trial(input) -> None`,
which raises on a crash."""

from __future__ import annotations

import argparse
import multiprocessing
import random
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))


def options(description: str, seconds: float = 60.0) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--seconds", type=float, default=seconds, help=f"how long to run (default {seconds:g})")
    parser.add_argument("--inputs", type=int, default=0, help="stop after this many inputs (0: only the time)")
    parser.add_argument("--seed", type=int, default=1, help="worker k draws from seed + k")
    parser.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    return parser.parse_args()


def _worker(job) -> tuple[int, int, list[str]]:
    name, make, trial, seed, seconds, limit = job
    rng = random.Random(seed)
    folder = ROOT / "build" / "fuzz" / name
    deadline = time.monotonic() + seconds
    inputs, saved = 0, []
    while time.monotonic() < deadline and (not limit or inputs < limit):
        data = make(rng)
        inputs += 1
        try:
            trial(data)
        except Exception:  # the point of the run: anything that escapes is a bug
            folder.mkdir(parents=True, exist_ok=True)
            path = folder / f"crash-{seed}-{inputs}.txt"
            path.write_text(f"{data}\n\n{traceback.format_exc()}", encoding="utf-8", errors="replace")
            saved.append(str(path))
    return inputs, len(saved), saved


def fuzz(name: str, make, trial, args: argparse.Namespace) -> int:
    """Run the workers; print the count, the rate and the crashes; exit 1 on any crash."""
    started = time.monotonic()
    per_worker = -(-args.inputs // args.workers) if args.inputs else 0
    jobs = [(name, make, trial, args.seed + k, args.seconds, per_worker) for k in range(args.workers)]
    if args.workers == 1:
        results = [_worker(jobs[0])]
    else:
        with multiprocessing.Pool(args.workers) as pool:
            results = pool.map(_worker, jobs)
    inputs = sum(r[0] for r in results)
    crashes = [path for r in results for path in r[2]]
    elapsed = time.monotonic() - started
    print(f"{name}: {inputs} inputs in {elapsed:.0f} s ({inputs / elapsed:.0f}/s, {args.workers} worker(s)), "
          f"{len(crashes)} crashes")
    for path in crashes[:20]:
        print(f"  {path}")
    return 1 if crashes else 0
