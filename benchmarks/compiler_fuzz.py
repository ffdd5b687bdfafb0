"""Differential fuzzing of the compiler, time-boxed, run on demand:
`python benchmarks/compiler_fuzz.py [--family avr|pic16|pic18|c] [--seconds 600] [--workers 2] [--seed N] [--out DIR]`.

Each worker draws random compilable programs for the family's boards
(tests/test_compiler_random.py), runs each in simavr (AVR), gpsim (PIC16) or
as C built by the host's compiler under the sanitizers (c) under its random
stimulus and compares every name with the simulator after
every scan. The report is how many programs were reached (goal: 1,000) and
every mismatch, each saved as an .ld file with its stimulus for replay. A
program too large for its part's flash is skipped, and so is one whose scan
outlasts the cycle at its board's crystal (counted: gpsim finds them).
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

GOAL = 1000
# family -> (the harness module with its differential, the generator's boards, the simulator run)
FAMILIES = {"avr": ("test_compiler_harness", "BOARDS", "simavr"),
            "pic16": ("pic16_harness", "PIC16_BOARDS", "gpsim"),
            "pic18": ("pic16_harness", "PIC18_BOARDS", "gpsim"),
            "c": ("c_harness", "C_BOARDS", "the host's C compiler with -fsanitize=undefined,address")}


class TimeUp(BaseException):
    """Ends a worker's run from inside hypothesis, which does not treat a
    BaseException as a failing example."""


def worker(args: tuple[str, int, float, str]) -> tuple[int, int, list[str]]:
    family, seed_value, deadline, out = args
    import importlib

    import test_compiler_random
    from hypothesis import HealthCheck, Phase, given, seed, settings
    from pic16_harness import CycleOverrun
    from test_compiler_random import cases, too_large

    from compiler.errors import CompileError
    from lang.ldfile import write_ld

    harness, boards, _ = FAMILIES[family]
    differential = importlib.import_module(harness).differential
    reached, overruns, failures = 0, 0, []
    seen: set[str] = set()  # hypothesis repeats itself: each program and stimulus counts once

    @seed(seed_value)
    @settings(max_examples=10**9, deadline=None, database=None, phases=[Phase.generate],
              suppress_health_check=list(HealthCheck))
    @given(case=cases(getattr(test_compiler_random, boards)))
    def run(case):
        nonlocal reached, overruns
        if time.monotonic() > deadline:
            raise TimeUp
        stimulus = "\n".join(f"; scan {e.scan}: {e.name} = {e.value}" for e in case.events)
        text = write_ld(case.program) + f"\n; {case.scans} scans\n{stimulus}\n"
        if text in seen:
            return
        seen.add(text)
        with tempfile.TemporaryDirectory() as tmp:
            try:
                problems = differential(case.program, case.events, case.scans, Path(tmp))
            except CompileError as error:
                if too_large(error):
                    return
                problems = [f"CompileError: {error}"]
            except CycleOverrun:
                overruns += 1
                return
            except Exception as error:  # noqa: BLE001  (a crash is a finding too)
                problems = [f"{type(error).__name__}: {error}"]
        reached += 1
        if problems:
            path = Path(out) / f"mismatch-{family}-{seed_value}-{reached}.ld"
            path.write_text(text + "; " + "\n; ".join(problems))
            failures.append(f"{path}: {problems[0]}")

    try:
        run()
    except TimeUp:
        pass
    return reached, overruns, failures


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--family", choices=sorted(FAMILIES), default="avr")
    parser.add_argument("--seconds", type=float, default=600)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=int(time.time()) % 100_000,
                        help="worker n draws from seed N+n (default: from the clock; printed to replay)")
    parser.add_argument("--out", default=tempfile.mkdtemp(prefix="compiler-fuzz-"))
    args = parser.parse_args()
    Path(args.out).mkdir(parents=True, exist_ok=True)
    started = time.monotonic()
    deadline = started + args.seconds
    with multiprocessing.get_context("spawn").Pool(args.workers) as pool:
        results = pool.map(worker, [(args.family, args.seed + n, deadline, args.out) for n in range(args.workers)])
    reached = sum(r for r, _, _ in results)
    overruns = sum(o for _, o, _ in results)
    failures = [f for _, _, fs in results for f in fs]
    elapsed = time.monotonic() - started
    print(f"{reached} distinct programs compiled, run in {FAMILIES[args.family][2]} and compared scan for scan in {elapsed:.0f} s on "
          f"{args.workers} workers (goal {GOAL}, seed {args.seed}): {len(failures)} mismatches; {overruns} more "
          "skipped, their scan longer than the cycle")
    for failure in failures:
        print("  " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
