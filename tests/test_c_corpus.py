"""The C of every program of the corpus and of tests/pic16_programs that
`ladder build --emit c` takes (every instruction has the `c` column, no
other error): built by the host's compiler under
-fsanitize=undefined,address and run beside the simulator, every input
switching at its own pace and the A/D readings moving, equal on every name
after every scan. A program the simulator itself stops (a division by zero
under this stimulus, say) is compared up to that scan."""

from __future__ import annotations

from pathlib import Path

import pytest
from c_harness import run_c
from corpus import CORPUS
from test_compiler_harness import Event, mismatches

from compiler.run import c as c_run
from lang.checks import check_program
from lang.diagnostics import ERROR
from lang.loader import load_path
from lang.sim import SimulationError, Simulator

PIC16_PROGRAMS = Path(__file__).parent / "pic16_programs"
SCANS = 300


def _c_programs() -> list[Path]:
    """Those `ladder build --emit c` takes: no reading error, no error for a build in C."""
    found = []
    for path in sorted(CORPUS.rglob("*.ld")) + sorted(PIC16_PROGRAMS.glob("*.ld")):
        program, diagnostics = load_path(path)
        diagnostics += check_program(program, True, family="c")
        if not any(d.severity == ERROR for d in diagnostics):
            found.append(path)
    return found


def _stimulus(program) -> list[Event]:
    names = sorted({str(v) for _, e in program.elements() for v in e.args.values() if str(v)[:1] in ("X", "A")
                    and str(v)[1:].isidentifier()})
    events = []
    for i, name in enumerate(names):
        period = 7 + 5 * i
        for scan in range(0, SCANS, period):
            value = (scan // period) % 2 if name[0] == "X" else (scan * 37 + 101 * i) % 1024
            events.append(Event(scan, name, value))
    return events


def _simulated(program, events: list[Event], names: list[str]) -> list[dict[str, int]]:
    sim, rows = Simulator(program), []
    for scan in range(SCANS):
        for event in events:
            if event.scan == scan:
                sim.set(event.name, event.value)
        try:
            sim.step()
        except SimulationError:
            break
        rows.append({n: sim.value(n) for n in names})
    return rows


PROGRAMS = _c_programs()


def test_most_of_the_corpus_is_c():
    assert len(PROGRAMS) >= 40


@pytest.mark.skipif(not c_run.available(), reason="no C compiler (Debian: gcc)")
@pytest.mark.parametrize("path", PROGRAMS, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_the_c_follows_the_simulator_scan_for_scan(path, tmp_path):
    program, _ = load_path(path)
    events = _stimulus(program)
    names, actual = run_c(program, events, SCANS, tmp_path)
    expected = _simulated(program, events, names)
    assert mismatches(expected, actual[:len(expected)], names) == []
