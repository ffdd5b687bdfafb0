"""Running a compiled program in simavr beside the simulator, scan for scan.

A stimulus is a list of (scan, name, value): the simulator applies it before
that scan; simavr drives the pin (or sets the A/D voltage) 0.05 cycle before
the scan starts, and sends a UART byte 0.75 cycle before: simavr delivers a
byte up to about 1.1 ms later at 9600 baud (its receiver ticks once a byte
time), so it must come after the scan before it has ended and in time for its
own (not for scan 0). After each scan, at 0.9 cycle when it is over, the
harness reads the data space, and the comparison takes every name both sides
have: output latches, relays, variables. The helpers are shared by the
compiler's end-to-end tests and benchmarks.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import pytest

import compiler
from compiler.run import simavr as sa
from lang.loader import load_path
from lang.model import Program
from lang.sim import Simulator

SHARED = Path(__file__).resolve().parents[2] / "shared"
CORPUS = SHARED / "corpus" / "ldmicro"
LDMICRO_HEX = SHARED / "corpus" / "ldmicro-hex"
IN_CI = bool(os.environ.get("CI"))
needs_simavr = pytest.mark.skipif(not sa.available() and not IN_CI, reason="gcc + libsimavr-dev not installed")

ADC_REFERENCE_MV = 5000  # the harness's AREF and AVCC
SAMPLE_AT, DRIVE_BEFORE, SEND_BEFORE = 0.9, 0.05, 0.75  # fractions of a cycle


@dataclass(frozen=True)
class Event:
    scan: int
    name: str  # an input, an A name (A/D reading), or "uart" (a received byte)
    value: int


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


def adc_millivolts(reading: int) -> int:
    """The voltage simavr converts to `reading` (it scales by 1023/AREF... 1024)."""
    return -(-reading * ADC_REFERENCE_MV // 1023)


@dataclass
class HexRun:
    values: list[dict[str, int]]
    run: sa.AvrRun


def _pin_of(build, name: str) -> str:
    device = build.device
    pin = device.pin(build.program.pins[name].pin)
    return f"{pin.port}{pin.bit}"


def _adc_channel(build, name: str) -> int:
    device = build.device
    return device.adc[device.pin(build.program.pins[name].pin).name]


def run_hex(build, hex_path: Path, events: list[Event], scans: int, names: list[str],
            watch: list[str] = ()) -> HexRun:
    """Run the image under the stimulus; the values of `names` read from the
    data space after each scan (and the edges of the `watch` pins)."""
    settings = build.program.settings
    freq, cycle_ms = settings.crystal_hz, settings.cycle_us / 1000

    def cycle_at(ms: float) -> int:
        return round(ms * freq / 1000)

    commands: list[tuple[int, int, str]] = []
    for name in watch:
        port, bit = _pin_of(build, name)
        commands.append((0, 0, f"watch {port} {bit}"))
    for event in events:
        lead = SEND_BEFORE if event.name == "uart" else DRIVE_BEFORE
        at = cycle_at(max(0.0, (event.scan - lead) * cycle_ms))
        if event.name == "uart":
            commands.append((at, 1, f"uart_in {event.value}"))
        elif event.name[0] == "X":
            port, bit = _pin_of(build, event.name)
            commands.append((at, 1, f"drive {port} {bit} {event.value}"))
        else:
            commands.append((at, 1, f"adc {_adc_channel(build, event.name)} {adc_millivolts(event.value)}"))
    symbols = {n: build.image.symbols[n] for n in names}
    spans = _spans(symbols)
    for scan in range(scans):
        at = cycle_at((scan + SAMPLE_AT) * cycle_ms)
        commands += [(at, 2, f"peek {start} {length}") for start, length in spans]
    commands.sort(key=lambda c: (c[0], c[1]))
    script = []
    for at, _, command in commands:
        if at:
            script.append(f"run_to {at}")
        script.append(command)
    run = sa.run_avr(hex_path, build.device.part, freq, script, timeout=300)
    memory: list[dict[int, int]] = []
    for line in run.raw.splitlines():
        if line.startswith("@peek"):
            fields = line.split()
            start = int(fields[1])
            if start == spans[0][0]:
                memory.append({})
            memory[-1].update({start + i: int(b, 16) for i, b in enumerate(fields[2:])})
    return HexRun([{n: _value(s, data) for n, s in symbols.items()} for data in memory], run)


def _spans(symbols: dict) -> list[tuple[int, int]]:
    """Few peek ranges covering every address."""
    addresses = sorted({s.address + i for s in symbols.values() for i in range(s.size)})
    spans: list[list[int]] = []
    for address in addresses:
        if spans and address - spans[-1][1] <= 16:
            spans[-1][1] = address
        else:
            spans.append([address, address])
    return [(a, b - a + 1) for a, b in spans] or [(0, 1)]


def _value(symbol, data: dict[int, int]) -> int:
    if symbol.bit is not None:
        return data[symbol.address] >> symbol.bit & 1
    raw = bytes(data[symbol.address + i] for i in range(symbol.size))
    return int.from_bytes(raw, "little", signed=True)


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
    spans = _spans(symbols)
    covered = {start + i for start, length in spans for i in range(length)}
    assert {3, 5, 0x100, 0x103, 0x130, 0x131} <= covered
    assert len(spans) == 3
