"""Simulator speed, run on demand: `python benchmarks/sim_bench.py`.

Scans per second with tracing off (Simulator.step(n) runs n-1 untraced
scans) for sample/traffic.ld (target 100,000 scans/s) and for a generated
200-rung program (target 10,000 scans/s, i.e. 100x real time at a 10 ms
cycle). Machines are small and noisy: the figures are medians of several
runs, with their ratio to the target.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lang.loader import load_path  # noqa: E402
from lang.model import Element, Parallel, Program, Rung, Series, Settings  # noqa: E402
from lang.sim import Simulator  # noqa: E402

SHARED = ROOT.parent / "shared"
REPEATS = 7


def generated_program(rungs: int = 200) -> Program:
    """A plausible machine program: interlocks, timers, counters, comparisons,
    arithmetic and latches, cycling through eight rung shapes."""
    def e(kind, /, **args):
        return Element(kind, args)

    shapes = []
    for i in range(rungs):
        x, y, r = f"X{i % 16}", f"Y{i % 24}", f"R{i}"
        shape = i % 8
        if shape == 0:
            items = [e("CONTACTS", name=x, negated=0, set1=0), e("CONTACTS", name=f"R{i - 1}", negated=1, set1=0),
                     e("TON", name=f"T{i}", delay=500000, adjust=0), e("COIL", name=r, type=" ")]
        elif shape == 1:
            items = [Parallel([e("CONTACTS", name=x, negated=0, set1=0), e("CONTACTS", name=r, negated=0, set1=0)]),
                     e("CONTACTS", name=f"X{(i + 3) % 16}", negated=1, set1=0),
                     Parallel([e("COIL", name=r, type=" "), e("COIL", name=y, type=" ")])]
        elif shape == 2:
            items = [e("CONTACTS", name=f"R{i - 2}", negated=0, set1=0),
                     e("CTU", name=f"C{i}", max="100", init="0", kind="/"), e("COIL", name=r, type=" ")]
        elif shape == 3:
            items = [e("GEQ", op1=f"C{i - 1}", op2="10"), e("LES", op1=f"C{i - 1}", op2="50"),
                     e("COIL", name=y, type=" ")]
        elif shape == 4:
            items = [e("CONTACTS", name=f"R{i - 4}", negated=0, set1=0),
                     e("ADD", dest=f"v{i}", op1=f"v{i}", op2="1")]
        elif shape == 5:
            items = [e("CONTACTS", name=x, negated=0, set1=0), e("OSR"),
                     Parallel([e("COIL", name=r, type="S"), e("MOVE", dest=f"v{i - 1}", src="0")])]
        elif shape == 6:
            items = [e("CONTACTS", name=f"R{i - 1}", negated=0, set1=0),
                     e("TOF", name=f"T{i}", delay=200000, adjust=0), e("COIL", name=y, type=" ")]
        else:
            items = [e("CONTACTS", name=f"Y{(i + 1) % 24}", negated=0, set1=0), e("CONTACTS", name=x, negated=0, set1=0),
                     e("COIL", name=f"R{i - 7}", type="R")]
        shapes.append(Rung(Series(items)))
    return Program(Settings(cycle_us=10000), shapes)


def scans_per_second(sim: Simulator, scans: int, toggles: list[str]) -> float:
    """Median speed over several batches; inputs change between batches so
    that the program does not settle into doing nothing."""
    rates = []
    for repeat in range(REPEATS):
        for i, name in enumerate(toggles):
            sim.set_input(name, (repeat + i) % 2)
        start = time.perf_counter()
        sim.step(scans)
        rates.append(scans / (time.perf_counter() - start))
    return statistics.median(rates)


def report(label: str, rate: float, target: float, cycle_us: int) -> None:
    real_time = rate * cycle_us / 1e6
    print(f"{label:<28} {rate:>12,.0f} scans/s   {rate / target:5.2f}x target ({target:,.0f})   "
          f"{real_time:,.0f}x real time")


def main() -> int:
    traffic, _ = load_path(SHARED / "corpus" / "ldmicro" / "sample" / "traffic.ld")
    sim = Simulator(traffic)
    sim.step(1000)
    report("traffic.ld", scans_per_second(sim, 50_000, ["Xbutton1", "Xbutton2"]), 100_000,
           traffic.settings.cycle_us)

    big = generated_program()
    sim = Simulator(big)
    sim.step(100)
    report("generated 200 rungs", scans_per_second(sim, 5_000, [n for n in sim.variables() if n.startswith("X")]), 10_000,
           big.settings.cycle_us)
    return 0


if __name__ == "__main__":
    sys.exit(main())
