"""Our simulator against LDmicro's own compiled HEX files, run in simavr (AVR)
and gpsim (PIC16) under the same written stimuli (every input driven from
time 0: undriven AVR inputs would read 1 through the pull-ups).

Timing: our scan k runs at k x cycle; the MCU runs its k-th scan one cycle
later (the cycle timer fires first) and writes a pin a few microseconds into
the scan. An edge matches when the HEX edge's scan, the cycle boundary just
before it, is within one scan of ours, and both sides make the same
sequence of levels on every output.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from compiler.run import gpsim as gp
from compiler.run import simavr as sa
from lang.loader import load_path
from lang.sim import Simulator
from lang.sim.trace import Trace

SHARED = Path(__file__).resolve().parents[2] / "shared"
CORPUS = SHARED / "corpus" / "ldmicro"
HEX = SHARED / "corpus" / "ldmicro-hex"
IN_CI = bool(os.environ.get("CI"))
needs_simavr = pytest.mark.skipif(not sa.available() and not IN_CI, reason="gcc + libsimavr-dev not installed")
needs_gpsim = pytest.mark.skipif(not gp.available() and not IN_CI, reason="gpsim not installed")


def our_edges(source: Path, stimuli, outputs, until_ms: float) -> tuple[dict, int]:
    program, _ = load_path(source)
    sim = Simulator(program)
    trace = Trace.watching(sim, outputs)
    events = sorted(stimuli)
    pending = 0
    while sim.time_ms <= until_ms:
        while pending < len(events) and events[pending][0] <= sim.time_ms:
            sim.set_input(events[pending][1], events[pending][2])
            pending += 1
        sim.step()
        trace.record(sim)
    edges = {name: [(t / 1000, v) for t, v in trace.changes[name]] for name in outputs}
    return edges, sim.cycle_us / 1000


def assert_same_edges(ours: dict, theirs: dict, cycle_ms: float) -> None:
    for name, mine in ours.items():
        hexed = theirs[name]
        assert [v for _, v in mine] == [v for _, v in hexed], f"{name}: ours {mine}, HEX {hexed}"
        for (t_ours, _), (t_hex, _) in zip(mine, hexed):
            hex_scan = (t_hex // cycle_ms) * cycle_ms
            assert abs(hex_scan - t_ours) <= cycle_ms, f"{name}: edge at {t_ours} ms, HEX at {t_hex:.3f} ms"


TRAFFIC_PINS = {"Xbutton1": "A5", "Xbutton2": "A6", "Yred": "A0", "Yyellow": "A1", "Ygreen": "A2", "Ywait": "A3"}


@needs_simavr
@pytest.mark.parametrize("presses", [[], [(2000, 0), (2100, 1)], [(9000, 0), (9400, 1), (13000, 0), (13050, 1)]])
def test_traffic_matches_avr_hex(presses):
    stimuli = [(0, "Xbutton1", 1), (0, "Xbutton2", 1)] + [(t, "Xbutton1", v) for t, v in presses]
    outputs = ["Yred", "Yyellow", "Ygreen", "Ywait"]
    ours, cycle = our_edges(CORPUS / "sample" / "traffic.ld", stimuli, outputs, 21_000)
    run = sa.simulate_avr(HEX / "sample_traffic.hex", "atmega128", 4_000_000, until_ms=21_000,
                          inputs=[(t, TRAFFIC_PINS[n], v) for t, n, v in stimuli],
                          watch=[TRAFFIC_PINS[o] for o in outputs])
    assert_same_edges(ours, {o: run.pin_edges_ms(TRAFFIC_PINS[o]) for o in outputs}, cycle)


TIMER_PINS = {"Xdown": "E0", "Xres": "E1", "Xup": "E2", "Ydown": "D2", "Ypulse": "A5", "Yup": "F5"}


@needs_simavr
@pytest.mark.parametrize("stimuli", [
    [(0, "Xdown", 0), (0, "Xres", 0), (0, "Xup", 1), (8000, "Xres", 1), (8100, "Xres", 0)],
    [(0, "Xdown", 0), (0, "Xres", 0), (0, "Xup", 1), (3000, "Xup", 0), (3000, "Xdown", 1),
     (6000, "Xdown", 0), (6500, "Xres", 1), (6520, "Xres", 0)],
])
def test_timers_and_counters_match_avr_hex(stimuli):
    outputs = ["Ydown", "Ypulse", "Yup"]
    ours, cycle = our_edges(CORPUS / "reg" / "tests" / "timers-counters.ld", stimuli, outputs, 18_500)
    run = sa.simulate_avr(HEX / "reg_tests_timers-counters.hex", "atmega128", 4_000_000, until_ms=18_500,
                          inputs=[(t, TIMER_PINS[n], v) for t, n, v in stimuli],
                          watch=[TIMER_PINS[o] for o in outputs])
    assert_same_edges(ours, {o: run.pin_edges_ms(TIMER_PINS[o]) for o in outputs}, cycle)


CONTACT_PINS = {"Xa": "RA0", "Xb": "RA1", "Xc": "RA2", "Xd": "RA3", "Xe": "RA4",
                "Yg": "RA5", "Yf": "RC0", "Yh": "RC1"}


@needs_gpsim
def test_contacts_match_pic_hex():
    steps = [(0, "Xa", 0), (0, "Xb", 0), (0, "Xc", 0), (0, "Xd", 0), (0, "Xe", 0),
             (100, "Xa", 1), (200, "Xa", 0), (300, "Xb", 1), (350, "Xb", 0), (400, "Xd", 1),
             (500, "Xe", 1), (600, "Xc", 1), (650, "Xc", 0), (700, "Xe", 0), (800, "Xd", 0),
             (850, "Xb", 1), (870, "Xd", 1), (880, "Xb", 0)]
    outputs = ["Yf", "Yg", "Yh"]
    ours, cycle = our_edges(CORPUS / "reg" / "tests" / "contacts.ld", steps, outputs, 950)
    run = gp.run_pic(HEX / "reg_tests_contacts.hex", "p16f876", 4_000_000, until_ms=950,
                     inputs=[(t, CONTACT_PINS[n], v) for t, n, v in steps],
                     watch=[CONTACT_PINS[o] for o in outputs])
    assert_same_edges(ours, {o: run.pin_edges(CONTACT_PINS[o]) for o in outputs}, cycle)
