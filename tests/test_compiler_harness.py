"""Running a compiled program in simavr beside the simulator, scan for scan
(compiler.run.record makes the recording: how the stimulus is timed, when
the data space is read): the comparison takes every name both sides have,
output latches, relays, variables. The helpers are shared by the compiler's
end-to-end tests and benchmarks."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import pytest

import compiler
from compiler.run import simavr as sa
from compiler.run.record import Event, adc_millivolts, record_avr, spans  # noqa: F401  (shared with other tests)
from lang.loader import load_path
from lang.model import Program
from lang.sim import Simulator

SHARED = Path(__file__).resolve().parents[2] / "shared"
CORPUS = SHARED / "corpus" / "ldmicro"
LDMICRO_HEX = SHARED / "corpus" / "ldmicro-hex"
IN_CI = bool(os.environ.get("CI"))
needs_simavr = pytest.mark.skipif(not sa.available() and not IN_CI, reason="gcc + libsimavr-dev not installed")


def load(relative: str) -> Program:
    program, _ = load_path(CORPUS / relative)
    return program


def simulate(program: Program, events: list[Event], scans: int, names: list[str]) -> list[dict[str, int]]:
    """The simulator's values of `names` after each scan."""
    sim = Simulator(program)
    pending = sorted(events, key=lambda e: e.scan)
    values, i = [], 0
    for scan in range(scans):
        while i < len(pending) and pending[i].scan <= scan:
            event = pending[i]
            if event.name == "uart":
                sim.uart_receive(bytes([event.value]))
            else:
                sim.set(event.name, event.value)
            i += 1
        sim.step()
        values.append({n: sim.value(n) for n in names})
    return values


def run_hex(build, hex_path: Path, events: list[Event], scans: int, names: list[str], watch: list[str] = ()):
    """The recording's rows and simavr's run (compiler.run.record)."""
    recording, run = record_avr(build, hex_path, events, scans, names, watch)
    return HexRun(recording.rows, run)


@dataclass
class HexRun:
    values: list[dict[str, int]]
    run: sa.AvrRun


def compared_names(program: Program, build) -> list[str]:
    """What both sides have and mean the same by: every name of the program
    but the inputs (the stimulus), `#` registers (hardware on the MCU, plain
    variables in the simulator) and a YPlcCycleDuty the runtime drives."""
    sim = Simulator(program)
    skip = {"YPlcCycleDuty"} if program.settings.cycle_duty else set()
    return sorted(n for n in sim.variables() if n in build.image.symbols and n[0] not in "X#" and n not in skip)


def differential(program: Program, events: list[Event], scans: int, tmp_path: Path, target: str | None = None,
                 names: list[str] | None = None) -> list[str]:
    """Mismatches between the simulator and the compiled image, as text
    (empty when they agree on every name after every scan)."""
    build = compiler.build(program, target)
    hex_path = tmp_path / "program.hex"
    build.write(hex_path)
    program = build.program
    names = compared_names(program, build) if names is None else names
    expected = simulate(program, events, scans, names)
    actual = run_hex(build, hex_path, events, scans, names).values
    assert len(actual) == scans, f"simavr gave {len(actual)} samples for {scans} scans"
    return mismatches(expected, actual, names)


def mismatches(expected: list[dict[str, int]], actual: list[dict[str, int]], names: list[str]) -> list[str]:
    """The first 20 differences, scan by scan, as text."""
    problems = [f"scan {scan}: {name} simulator {want[name]}, compiled {got[name]}"
                for scan, (want, got) in enumerate(zip(expected, actual)) for name in names if want[name] != got[name]]
    return problems[:20]


# --- the helpers themselves -------------------------------------------------------------------

@needs_simavr
@pytest.mark.slow
def test_a_simple_program_matches_scan_for_scan(tmp_path):
    program = load("sample/traffic.ld")
    events = [Event(0, "Xbutton1", 1), Event(0, "Xbutton2", 1), Event(120, "Xbutton1", 0),
              Event(125, "Xbutton1", 1)]
    assert differential(program, events, 400, tmp_path) == []


def test_peek_spans_cover_every_address():
    from compiler.image import Symbol

    symbols = {"a": Symbol(3, 1, 0), "b": Symbol(0x100, 4), "c": Symbol(0x130, 2), "d": Symbol(5, 1, 2)}
    ranges = spans(symbols)
    covered = {start + i for start, length in ranges for i in range(length)}
    assert {3, 5, 0x100, 0x103, 0x130, 0x131} <= covered
    assert len(ranges) == 3
