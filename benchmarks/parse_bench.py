"""Parse + check time for a generated 2,000-rung text file, and for the same
file after a one-character edit in one rung (what the language server sees).

Run on demand: `python benchmarks/parse_bench.py`. Figures are medians of
several runs; the machine is small and noisy, so compare ratios in one run."""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from lang.checks import check_program  # noqa: E402
from lang.model import Element, Parallel, PinAssignment, Program, Rung, Series, Settings, rung_circuit  # noqa: E402
from lang.textform import reader  # noqa: E402
from lang.textform.writer import render_program  # noqa: E402

RUNGS = 2000


def contact(name, negated=0):
    return Element("CONTACTS", {"name": name, "negated": negated, "set1": 0})


def big_program() -> Program:
    """A plausible large program: seal-in rungs, timers, counters, compares, moves."""
    rungs = []
    for i in range(RUNGS):
        kind = i % 5
        if kind == 0:
            circuit = Series([Parallel([contact(f"Xin{i % 40}"), contact(f"Rm{i}")]), contact(f"Xstop{i % 7}", 1),
                              Element("COIL", {"name": f"Rm{i}", "type": " "})])
        elif kind == 1:
            circuit = Series([contact(f"Rm{i - 1}"), Element("TON", {"name": f"Tt{i}", "delay": 1500000, "adjust": 0}),
                              Element("COIL", {"name": f"Yout{i % 20}", "type": " "})])
        elif kind == 2:
            circuit = Series([contact(f"Rm{i - 2}"), Element("CTU", {"name": f"Cc{i}", "max": "10", "init": "0", "kind": "/"}),
                              Element("COIL", {"name": f"Rdone{i}", "type": "S"})])
        elif kind == 3:
            circuit = Series([Element("GEQ", {"op1": f"Cc{i - 1}", "op2": "5"}),
                              Element("MOVE", {"dest": f"val{i}", "src": "123"})])
        else:
            circuit = Series([contact(f"Rdone{i - 2}"), Element("ADD", {"dest": f"sum{i}", "op1": f"sum{i}", "op2": "1"})])
        rungs.append(Rung(rung_circuit(circuit)))
    program = Program(settings=Settings(mcu="Atmel AVR ATmega2560 100-TQFP"), rungs=rungs)
    for n in range(40):
        program.pins[f"Xin{n}"] = PinAssignment(f"Xin{n}", f"PA{n % 8}" if n < 8 else 1)
    return program


def timed(function, repeat=7):
    samples = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        samples.append(time.perf_counter() - start)
    return statistics.median(samples) * 1000


def main() -> None:
    text = render_program(big_program())
    lines = text.splitlines(keepends=True)
    target = next(i for i, line in enumerate(lines) if line.startswith("1001|"))
    edited = "".join(lines[:target - 1]) + lines[target - 1].replace("Rm1000", "Rm1001", 1) + "".join(lines[target:])

    def cold():
        reader._CACHE.clear()
        program, _ = reader.read_text(text)
        check_program(program)

    def warm_edit():
        reader.read_text(text)  # the cache holds the unchanged rungs, as in the server
        program, _ = reader.read_text(edited)
        check_program(program)

    def edit_only():
        program, _ = reader.read_text(edited)
        check_program(program)

    reader.read_text(text)
    cold_ms = timed(cold, 3)
    parse_only = timed(lambda: (reader._CACHE.clear(), reader.read_text(text)), 3)
    program, _ = reader.read_text(text)
    check_ms = timed(lambda: check_program(program))
    edit_ms = timed(edit_only)
    print(f"{RUNGS} rungs, {len(lines)} lines, {len(text) / 1e6:.2f} MB")
    print(f"parse + check, cold:               {cold_ms:7.1f} ms   (target < 300 ms)")
    print(f"  of which parse:                  {parse_only:7.1f} ms")
    print(f"  of which check:                  {check_ms:7.1f} ms")
    print(f"parse + check after a 1-rung edit: {edit_ms:7.1f} ms   (target < 20 ms)")


if __name__ == "__main__":
    main()
