"""Simulator speed, run on demand: `python benchmarks/sim_bench.py`.

Scans per second with tracing off (Simulator.step(n) runs n-1 untraced
scans) for sample/traffic.ld and for a generated 200-rung program, against
targets that are the simulator's speed before its instructions moved to the
one lowering (lang/semantics): 2.3 M and 124 k scans/s here. Machines are
small and noisy: the figures are medians of several runs, with their ratio
to the target.

`--against DIR` measures another checkout (say, the commit before a change)
in the same run: each side in its own process, in turn, three rounds, and
prints the median ratio of this tree's speed to that one's.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
# the checkout whose simulator is measured: this one, or the --root of a run for --against
ROOT = Path(sys.argv[sys.argv.index("--root") + 1]).resolve() if "--root" in sys.argv else HERE
sys.path.insert(0, str(ROOT))

from lang.loader import load_path  # noqa: E402
from lang.model import Element, Parallel, Program, Rung, Series, Settings  # noqa: E402
from lang.sim import Simulator  # noqa: E402

SHARED = HERE.parent / "shared"
REPEATS = 7
ROUNDS = 3
TRAFFIC_TARGET = 2_300_000
GENERATED_TARGET = 124_000
CYCLE_US = 10_000  # both programs' cycle time


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
    return Program(Settings(cycle_us=CYCLE_US), shapes)


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


def report(label: str, rate: float, target: float) -> None:
    real_time = rate * CYCLE_US / 1e6
    print(f"{label:<28} {rate:>12,.0f} scans/s   {rate / target:5.2f}x target ({target:,.0f})   "
          f"{real_time:,.0f}x real time")


def measure() -> dict[str, float]:
    traffic, _ = load_path(SHARED / "corpus" / "ldmicro" / "sample" / "traffic.ld")
    sim = Simulator(traffic)
    sim.step(1000)
    rates = {"traffic.ld": scans_per_second(sim, 50_000, ["Xbutton1", "Xbutton2"])}
    big = generated_program()
    sim = Simulator(big)
    sim.step(100)
    rates["generated 200 rungs"] = scans_per_second(sim, 5_000, [n for n in sim.variables() if n.startswith("X")])
    return rates


def _measured_in(root: Path) -> dict[str, float]:
    out = subprocess.run([sys.executable, __file__, "--json", "--root", str(root)], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--json", action="store_true", help="print the rates as JSON")
    parser.add_argument("--against", type=Path, metavar="DIR", help="another checkout to compare with")
    parser.add_argument("--root", type=Path, metavar="DIR", help="the checkout to measure (default: this one)")
    args = parser.parse_args()
    if args.json:
        print(json.dumps(measure()))
        return 0
    if args.against:
        ratios: dict[str, list[float]] = {}
        for _ in range(ROUNDS):
            ours, theirs = _measured_in(HERE), _measured_in(args.against.resolve())
            for label in ours:
                ratios.setdefault(label, []).append(ours[label] / theirs[label])
                print(f"{label:<28} {ours[label]:>12,.0f} scans/s here, {theirs[label]:>12,.0f} there")
        for label, values in ratios.items():
            print(f"{label:<28} median ratio {statistics.median(values):.2f}x  ({', '.join(f'{v:.2f}' for v in values)})")
        return 0
    rates = measure()
    report("traffic.ld", rates["traffic.ld"], TRAFFIC_TARGET)
    report("generated 200 rungs", rates["generated 200 rungs"], GENERATED_TARGET)
    return 0


if __name__ == "__main__":
    sys.exit(main())
