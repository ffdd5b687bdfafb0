"""`ladder verify` speed, run on demand: `python benchmarks/verify_bench.py`.

A corpus-sized program (sim_bench.py's generated shapes, 100 rungs:
interlocks, timers, counters, comparisons, arithmetic, latches) with 20
properties of every kind, proved together as `ladder verify` does, at its
default bound. Prints each property's verdict, the induction length k that
decided it (or the scans searched), its time, and the total against the
target: 10 s on the 2-core machine the project runs on.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from sim_bench import generated_program

from lang.properties import parse_property
from lang.verify import DEFAULT_BOUND, DEFAULT_TIMEOUT_S, verify

TARGET_S = 10.0
RUNGS = 100

# about the generated shapes: rung i writes R<i> (and Y<i % 24>, C<i>, v<i>, T<i> by its shape)
PROPERTIES = [
    "always C2 <= 100",
    "always C10 in 0..100",
    "never Y3 and not (C2 >= 10)",
    "always T0 <= 50",
    "always T8 in 0..50",
    "never R7 and R7",
    "always R1 implies not R0",
    "always v4 >= 0",
    "reachable R2",
    "reachable C10 = 5",
    "R0 within 600 ms after X0 and not R1",
    "always Y6 implies R5",
    "never C18 > 100",
    "always T14 <= 20",
    "reachable Y11",
    "always R1 or not R1",
    "never X1 and not X1",
    "always C26 >= 0",
    "R5 within 10 ms after X5",
    "always v12 in -32768..32767",
]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bound", type=int, default=DEFAULT_BOUND)
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S)
    args = parser.parse_args()
    program = generated_program(RUNGS)
    properties = [parse_property(text, line) for line, text in enumerate(PROPERTIES)]
    started = time.perf_counter()
    results = verify(program, properties, args.bound, args.timeout)
    total = time.perf_counter() - started
    for result in results:
        decided = f"k = {result.k}" if result.k is not None else \
            f"scan {result.witness.scan + 1}" if result.witness is not None else f"{result.depth} scans"
        print(f"{result.seconds:7.3f} s  {result.verdict:<8} {decided:<10} {result.prop.text}")
    print(f"{total:7.3f} s  total for {len(properties)} properties on {RUNGS} rungs "
          f"({total / TARGET_S:.2f} of the {TARGET_S:g} s target)")
    return 0 if total <= TARGET_S else 1


if __name__ == "__main__":
    sys.exit(main())
