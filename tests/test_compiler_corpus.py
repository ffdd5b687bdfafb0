"""The corpus programs compiled and run in simavr: every name the simulator
and the image share agrees after every scan (test_compiler_harness.py), and
the output pins make the same edges as LDmicro's own HEX under the same
stimulus, within one scan (LDmicro's first scan comes one cycle after reset,
ours at once).

All these programs target AVR parts simavr has cores for, so they run on
their own part and pins. swatch2 writes whole ports through `#PORTB..D`
(registers on the MCU, plain variables in the simulator): there the port
registers are compared with those variables, and the Y latches they
overwrite are left out.
"""

from __future__ import annotations

import pytest
from test_compiler_harness import LDMICRO_HEX, Event, differential, load, needs_simavr

import compiler
from compiler.run import simavr as sa

TRAFFIC = [Event(0, "Xbutton1", 1), Event(0, "Xbutton2", 1), Event(200, "Xbutton1", 0), Event(210, "Xbutton1", 1),
           Event(900, "Xbutton2", 0), Event(904, "Xbutton2", 1)]
TIMERS = [Event(0, "Xdown", 0), Event(0, "Xres", 0), Event(0, "Xup", 1), Event(300, "Xup", 0),
          Event(300, "Xdown", 1), Event(600, "Xdown", 0), Event(650, "Xres", 1), Event(652, "Xres", 0),
          Event(700, "Xup", 1), Event(1200, "Xres", 1), Event(1210, "Xres", 0)]
SWATCH = [Event(0, "X_StartStopContinue", 1), Event(0, "X_StopZero", 1),
          Event(100, "X_StartStopContinue", 0), Event(160, "X_StartStopContinue", 1),
          Event(2500, "X_StartStopContinue", 0), Event(2560, "X_StartStopContinue", 1),
          Event(2900, "X_StopZero", 0), Event(2980, "X_StopZero", 1)]
ADC = [Event(0, "Ain", 100), Event(50, "Ain", 600), Event(80, "Ain", 500), Event(90, "Ain", 501),
       Event(100, "Ain", 1023), Event(110, "Ain", 0)]

CASES = {
    "sample/traffic.ld": (TRAFFIC, 2200),
    "reg/tests/timers-counters.ld": (TIMERS, 1800),
    "sample/ctu_ctd_ctc.ld": ([], 3000),
    "sample/ctu_ctd_ctc_ctr.ld": ([], 3000),
    "sample/hello.ld": ([], 700),
    "Tests/test-adc.ld": (ADC, 130),
}


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(CASES))
def test_compiled_program_follows_the_simulator(path, tmp_path):
    events, scans = CASES[path]
    assert differential(load(path), events, scans, tmp_path) == []


@needs_simavr
@pytest.mark.slow
def test_swatch2_follows_the_simulator_with_its_ports(tmp_path):
    program = load("sample/swatch2.ld")
    build = compiler.build(program)
    overwritten = {n for n in program.pins if n[0] == "Y" and n != "Yp5"}
    names = sorted(n for n in build.image.symbols if n[0] not in "X~$#" and n not in overwritten)
    names += ["#PORTC", "#PORTD"]
    assert differential(program, SWATCH, 3200, tmp_path, names=names) == []


def _edges(hex_path, mcu, freq, stimuli_ms, pins, until_ms):
    run = sa.simulate_avr(hex_path, mcu, freq, until_ms=until_ms, inputs=stimuli_ms, watch=pins)
    return {pin: run.pin_edges_ms(pin) for pin in pins}


def _pin(program, name: str, device) -> str:
    pin = device.pin(program.pins[name].pin)
    return f"{pin.port}{pin.bit}"


def _scan_counter(edges, duty: str | None, cycle_ms: float):
    """The scan an edge belongs to: counted on the YPlcCycleDuty pulses when
    the program has them (LDmicro's ATmega8 Timer0 cycle runs 0.09 % slow,
    so its scans drift off the time grid), else by time."""
    if duty is None:
        return lambda t: int(t // cycle_ms)
    starts = [t for t, v in edges[duty] if v]
    return lambda t: sum(1 for s in starts if s <= t)


LDMICRO = {
    "sample/traffic.ld": ("sample_traffic.hex", TRAFFIC, 2200),
    "reg/tests/timers-counters.ld": ("reg_tests_timers-counters.hex", TIMERS, 1800),
    "sample/ctu_ctd_ctc.ld": ("sample_ctu_ctd_ctc.hex", [], 3000),
    "sample/ctu_ctd_ctc_ctr.ld": ("sample_ctu_ctd_ctc_ctr.hex", [], 3000),
    "sample/swatch2.ld": ("sample_swatch2.hex", SWATCH, 3200),
}


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("path", sorted(LDMICRO))
def test_same_output_edges_as_ldmicros_hex(path, tmp_path):
    reference, events, scans = LDMICRO[path]
    same_edges_as_ldmicro(load(path), LDMICRO_HEX / reference, events, scans, tmp_path)


def same_edges_as_ldmicro(program, reference, events, scans, tmp_path) -> None:
    """Our image and LDmicro's HEX of the program make the same edges on
    every output pin under the same stimulus, each within one scan."""
    build = compiler.build(program)
    ours = tmp_path / "ours.hex"
    build.write(ours)
    device = build.device
    settings = program.settings
    cycle_ms = settings.cycle_us / 1000
    outputs = sorted(n for n in program.pins if n[0] == "Y" and n != "YPlcCycleDuty")
    pins = sorted({_pin(program, n, device) for n in outputs})
    duty = _pin(program, "YPlcCycleDuty", device) if settings.cycle_duty and "YPlcCycleDuty" in program.pins else None
    # both images see each input change half a cycle before the scan it is for
    stimuli = [(max(0.0, (e.scan - 0.5) * cycle_ms), _pin(program, e.name, device), e.value) for e in events]
    until = scans * cycle_ms
    watched = pins + ([duty] if duty else [])
    mine = _edges(ours, build.device.part, settings.crystal_hz, stimuli, watched, until)
    theirs = _edges(reference, build.device.part, settings.crystal_hz, stimuli, watched, until)
    our_scan, their_scan = _scan_counter(mine, duty, cycle_ms), _scan_counter(theirs, duty, cycle_ms)
    last = until - 3 * cycle_ms  # LDmicro runs one scan behind: its last edges may be cut off
    for pin in pins:
        a = [(t, v) for t, v in mine[pin] if t < last]
        b = theirs[pin][:len(a)]
        assert [v for _, v in a] == [v for _, v in b], f"{pin}: ours {a[:8]}, LDmicro {b[:8]}"
        for (t_ours, _), (t_theirs, _) in zip(a, b):
            assert abs(their_scan(t_theirs) - our_scan(t_ours)) <= 1, \
                f"{pin}: our edge at {t_ours:.3f} ms, LDmicro's at {t_theirs:.3f} ms"


@needs_simavr
@pytest.mark.slow
def test_traffic_moved_to_the_atmega328p_by_port_name(tmp_path):
    """`--target` semantics: the ATmega128 program's pins re-assigned by port
    name in the test (its package pin numbers do not exist on the 28-pin
    ATmega328P), then built for that part."""
    from lang.model import PinAssignment

    program = load("sample/traffic.ld")
    ports = {"Xbutton1": "PD2", "Xbutton2": "PD3", "Yred": "PB0", "Yyellow": "PB1", "Ygreen": "PB2", "Ywait": "PB3"}
    for name, port in ports.items():
        program.pins[name] = PinAssignment(name, port)
    assert differential(program, TRAFFIC, 2200, tmp_path, target="atmega328p") == []
