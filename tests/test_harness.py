"""The simulator harnesses (simavr for AVR, gpsim for PIC16), checked on LDmicro's own HEX
files: the outputs must do what the ladder source of each file says.

The .ld sources are in shared/corpus/ldmicro/ (sample/, reg/tests/, Tests/); the HEX files
(LDmicro's compiler output, the reference) in shared/corpus/ldmicro-hex/. Pin numbers in the
.ld IO LIST are package pins; the mapping to port bits is noted at each test.

Timing model used for the expectations: one PLC cycle every CYCLE µs (10 ms here), the first
cycle about one period after reset; a timer of delay D switches after D (± one cycle).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from compiler.run import gpsim as gp
from compiler.run import simavr as sa

REPO = Path(__file__).resolve().parents[1]
HEX = REPO.parent / "shared" / "corpus" / "ldmicro-hex"

# Skip only for a missing simulator; CI installs them (Debian simavr libsimavr-dev gpsim), so
# there a missing one is a failure, not a skip.
IN_CI = bool(os.environ.get("CI"))
needs_simavr = pytest.mark.skipif(not sa.available() and not IN_CI,
                                  reason="gcc + libsimavr-dev not installed")
needs_gpsim = pytest.mark.skipif(not gp.available() and not IN_CI, reason="gpsim not installed")

SCAN = 10.0  # ms: CYCLE=10000 in every .ld used here
TOL = 2 * SCAN


def hexfile(name: str) -> Path:
    path = HEX / name
    assert path.is_file(), f"missing reference HEX {path} (shared/ must sit beside the repo)"
    return path


def assert_edges(got: list[tuple[float, int]], want: list[tuple[float, int]], tol: float = TOL):
    """Same sequence of levels, each edge within tol ms of the expected time."""
    assert [v for _, v in got] == [v for _, v in want], f"edges {got} != expected {want}"
    for (tg, _), (tw, _) in zip(got, want):
        assert abs(tg - tw) <= tol, f"edge at {tg:.2f} ms, expected {tw:.2f} ms (±{tol}); {got}"


# =========================================================================== AVR (simavr)


@needs_simavr
def test_avr_traffic_lights_follow_the_cycle():
    """sample/traffic.ld, ATmega128 64-TQFP at 4 MHz. IO: Xbutton1 46 = PA5, Xbutton2 45 = PA6
    (active low: the ladder uses ]/[), Yred 51 = PA0, Yyellow 50 = PA1, Ygreen 49 = PA2,
    Ywait 48 = PA3.

    Rclock oscillates: ]/[Rclock -> TOF 500 ms -> TON 500 ms -> (Rclock): rises at 0.5 s,
    then every 1 s. CTC Ccycle 19 counts its rising edges (0..19, wraps). Red while
    Ccycle < 8, yellow 8..11, green 12..19: red ends at the 8th rise (7.5 s), yellow at the
    12th (11.5 s), green at the 20th (19.5 s), then red again. No button: Ywait stays off."""
    run = sa.simulate_avr(hexfile("sample_traffic.hex"), "Atmel AVR ATmega128 64-TQFP",
                          4_000_000, until_ms=21_000,
                          inputs=[(0, "A5", 1), (0, "A6", 1)],  # buttons released
                          watch=["A0", "A1", "A2", "A3"])
    assert run.levels == {"A0": 0, "A1": 0, "A2": 0, "A3": 0}
    assert_edges(run.pin_edges_ms("A0"), [(SCAN, 1), (7500, 0), (19500, 1)])   # red
    assert_edges(run.pin_edges_ms("A1"), [(7500, 1), (11500, 0)])              # yellow
    assert_edges(run.pin_edges_ms("A2"), [(11500, 1), (19500, 0)])             # green
    assert run.pin_edges_ms("A3") == []                                         # wait lamp
    # exactly one light on at any time (away from the switching instants)
    for t in range(100, 21_000, 250):
        assert sum(run.level_at(p, t) for p in ("A0", "A1", "A2")) == 1, t


@needs_simavr
def test_avr_traffic_wait_lamp_after_button():
    """Same program: pressing Xbutton1 (PA5 low) during red latches Rwait, so Ywait lights
    during red, follows Rclock during yellow (off 8.0, on 8.5, ... off 11.0 s: Rclock is high
    in the first half of each second after 7.5 s) and goes out for good when green resets
    Rwait. The light timing is unchanged (the rung's MOVE writes 'cycle', not 'Ccycle')."""
    run = sa.simulate_avr(hexfile("sample_traffic.hex"), "atmega128", 4_000_000,
                          until_ms=20_000,
                          inputs=[(0, "A5", 1), (0, "A6", 1), (2000, "A5", 0), (2100, "A5", 1)],
                          watch=["A0", "A1", "A2", "A3"])
    assert_edges(run.pin_edges_ms("A3"), [(2000, 1), (8000, 0), (8500, 1), (9000, 0),
                                          (9500, 1), (10000, 0), (10500, 1), (11000, 0)])
    assert_edges(run.pin_edges_ms("A1"), [(7500, 1), (11500, 0)])
    assert_edges(run.pin_edges_ms("A2"), [(11500, 1), (19500, 0)])


@needs_simavr
def test_avr_timers_and_counters():
    """reg/tests/timers-counters.ld, ATmega128 64-TQFP at 4 MHz. IO: Xdown 2 = PE0,
    Xres 3 = PE1, Xup 4 = PE2, Ydown 27 = PD2, Ypulse 46 = PA5, Yup 56 = PF5.

    Rosc: ]Rosc[ -> TOF 100 ms -> TON 100 ms -> (/Rosc): set in the first cycle (10 ms), then
    rises every 200 ms. With Xup = 1, Xdown = 0: CTU Ccnt counts every Rosc rise.
    * Ydown = CTD Ccnt 10 output (true when Ccnt > 10): the 11th rise, 10 + 10*200 = 2010 ms.
    * Yup = CTU (Ccnt >= 20, at the 20th rise: 3810 ms) then RTO 10 s; Xres pulsed at
      8.0-8.1 s resets the RTO on both edges (OSR || OSF -> RES), so Yup comes at 18.1 s.
    * Ypulse = ==(Ccirc, 3) -> OSF -> TOF 200 ms, Ccirc = CTC 7 of the Rosc rises: Ccirc
      leaves 3 at the 4th rise (610 ms) and every 8 rises after: a 200 ms pulse every 1.6 s."""
    run = sa.simulate_avr(hexfile("reg_tests_timers-counters.hex"), "atmega128", 4_000_000,
                          until_ms=18_500,
                          inputs=[(0, "E0", 0), (0, "E1", 0), (0, "E2", 1),
                                  (8000, "E1", 1), (8100, "E1", 0)],
                          watch=["D2", "A5", "F5"])
    assert_edges(run.pin_edges_ms("D2"), [(2010, 1)])
    assert_edges(run.pin_edges_ms("F5"), [(18100, 1)])
    pulses = []
    for k in range(12):
        pulses += [(610 + 1600 * k, 1), (810 + 1600 * k, 0)]
    assert_edges(run.pin_edges_ms("A5"), pulses)


@needs_simavr
def test_avr_hello_prints_its_text():
    """sample/hello.ld, ATmega8 at 16 MHz, 9600 baud: Rosc pulses once a second (]Rosc[ ->
    TON 1 s -> (/Rosc)), each pulse increments cnt and starts FORMATTED_STRING
    "Hello, world: \\-5\\r\\n" (cnt with sign, 5 digits). LDmicro sends one character per PLC
    cycle."""
    run = sa.simulate_avr(hexfile("sample_hello.hex"), "Atmel AVR ATmega8 28-PDIP", 16_000_000,
                          until_ms=2500)
    text = run.uart_bytes()
    assert text == (b"Hello, world:      1\r\n"
                    b"Hello, world:      2\r\n"
                    b"Hello, world:      3\r\n")
    times = [t for t, _ in run.uart_ms()]
    gaps = [b - a for a, b in zip(times, times[1:])]
    line_starts = [times[0], times[22], times[44]]
    assert all(abs(g - SCAN) < 0.5 for i, g in enumerate(gaps) if i not in (21, 43)), gaps
    # lines a TON period (1 s, plus the cycle the oscillator spends off) apart
    for a, b in zip(line_starts, line_starts[1:]):
        assert 1000 - 0.5 <= b - a <= 1000 + SCAN + 0.5, line_starts


@needs_simavr
def test_avr_adc_thresholds():
    """Tests/test-adc.ld, ATmega16 40-PDIP at 10 MHz: Ain 40 = PA0 = ADC0, Yled1 18 = PD4
    (on when Ain <= 500 counts), Yled2 19 = PD5 (on when Ain >= 501). counts = mV*1024/5000
    (simavr: AVCC = AREF = 5 V)."""
    steps = [(0, 1000), (100, 2430), (200, 2470), (300, 4000), (400, 0), (500, 5000)]
    run = sa.simulate_avr(hexfile("Tests_test-adc.hex"), "atmega16", 10_000_000,
                          until_ms=600, watch=["D4", "D5"],
                          adc=[(t, 0, mv) for t, mv in steps])
    want: dict[str, list[tuple[float, int]]] = {"D4": [], "D5": []}
    level = {"D4": 0, "D5": 0}
    for t, mv in steps:
        counts = mv * 1024 // 5000
        new = {"D4": int(counts <= 500), "D5": int(counts >= 501)}
        for pin in want:
            if new[pin] != level[pin]:
                want[pin].append((t + SCAN, new[pin]))  # seen by the next PLC cycle
            level[pin] = new[pin]
    for pin in want:
        assert_edges(run.pin_edges_ms(pin), want[pin])


# A tiny hand-made ATmega8 program (1 MHz) for the harness's own features: at every start it
# increments EEPROM[0] and shows the result on PORTB, then echoes each UART byte plus one.
#     ldi r17,0 / out EEARH,r17 / out EEARL,r17 / sbi EECR,EERE / in r16,EEDR / inc r16 /
#     out EEDR,r16 / sbi EECR,EEMWE / sbi EECR,EEWE / ldi r18,0xFF / out DDRB,r18 /
#     out PORTB,r16 / out UBRRH,r17 / ldi r16,25 / out UBRRL,r16 / ldi r16,0x18 /
#     out UCSRB,r16 / rx: sbis UCSRA,RXC / rjmp rx / in r17,UDR / inc r17 /
#     tx: sbis UCSRA,UDRE / rjmp tx / out UDR,r17 / rjmp rx
# (UBRRH is written before UBRRL: on the ATmega8 it shares its address with UCSRC, whose
# reset value would otherwise make simavr compute 40 baud.)
EE_PROGRAM = bytes.fromhex(
    "10e01fbb1ebbe09a0db303950dbbe29ae19a2fef27bb08bb10bd09e109b908e10ab9"
    "5f9bfecf1cb113955d9bfecf1cb9f8cf")


def _write_hex(path: Path, flash: bytes, eeprom: bytes | None = None) -> Path:
    from intelhex import IntelHex

    ih = IntelHex()
    ih.frombytes(flash, offset=0)
    if eeprom is not None:
        ih.frombytes(eeprom, offset=0x810000)  # avr-objcopy's EEPROM segment
    ih.write_hex_file(str(path))
    return path


@needs_simavr
def test_avr_harness_eeprom_reset_and_uart_in(tmp_path):
    hex_path = _write_hex(tmp_path / "ee.hex", EE_PROGRAM)
    run = sa.run_avr(hex_path, "atmega8", 1_000_000, [
        "run 1000", "read B", "eeprom_read 0 2",
        "reset", "run 1000", "read B", "eeprom_read 0 2",
        "uart_in 65", "uart_in 0x7a", "run 20000", "cycles"])
    # erased EEPROM reads 0xFF: first start writes 0x00, the second (after reset) 0x01
    assert run.ports == [("B", 0x00, 0xFF, 0x00), ("B", 0x01, 0xFF, 0x01)]
    assert run.eeprom == [b"\x00\xff", b"\x01\xff"]
    assert len(run.resets) == 1
    assert [b for _, b in run.uart] == [66, 0x7B]
    assert run.cycles[-1] >= 22_000


@needs_simavr
def test_avr_harness_loads_eeprom_from_hex(tmp_path):
    hex_path = _write_hex(tmp_path / "ee2.hex", EE_PROGRAM, eeprom=b"\x41\x00\x07")
    run = sa.run_avr(hex_path, "atmega8", 1_000_000, ["run 1000", "read B", "eeprom_read 0 3",
                                                       "peek 0x38"])
    assert run.port("B") == (0x42, 0xFF, 0x42)
    assert run.eeprom == [b"\x42\x00\x07"]
    assert "@peek 56 42" in run.raw   # PORTB at data address 0x38


@needs_simavr
def test_avr_harness_errors(tmp_path):
    # reg/tests/integers.ld targets the ATmega162: simavr has no such core
    with pytest.raises(sa.UnsupportedMcu):
        sa.run_avr(hexfile("reg_tests_integers.hex"), "Atmel AVR ATmega162 40-PDIP", 4_000_000,
                   ["run 100"])
    with pytest.raises(sa.UnsupportedMcu):
        sa.core_name("ATmega64")
    with pytest.raises(sa.HarnessError, match="bad command"):
        sa.run_avr(hexfile("sample_hello.hex"), "atmega8", 16_000_000, ["fly 100"])
    with pytest.raises(sa.HarnessError, match="no HEX"):
        sa.run_avr(tmp_path / "missing.hex", "atmega8", 16_000_000, [])
    # an ATmega128 image does not fit an ATmega8
    with pytest.raises(sa.HarnessError, match="flash"):
        big = _write_hex(tmp_path / "big.hex", b"\x00\x00" * 8192)
        sa.run_avr(big, "atmega8", 1_000_000, [])
    assert sa.core_name("Atmel AVR ATmega328 32-Pin packages") == "atmega328"
    assert sa.parse_pin("PB5") == ("B", 5)


def test_missing_simavr_names_the_debian_package(monkeypatch, tmp_path):
    monkeypatch.setattr(sa, "SIMAVR_INCLUDE", tmp_path / "nowhere")
    monkeypatch.setattr(sa, "_built", None)
    monkeypatch.setattr(sa, "_build_error", None)
    assert not sa.available()
    with pytest.raises(sa.HarnessError, match="install the Debian package libsimavr-dev"):
        sa.run_avr(hexfile("sample_hello.hex"), "atmega8", 16_000_000, ["run 100"])


@needs_simavr
def test_the_avr_harness_is_built_in_the_cache_not_the_package(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(sa, "_built", None)
    monkeypatch.setattr(sa, "_build_error", None)
    exe = sa.build_harness()
    assert exe.parent == tmp_path / "textladder" and os.access(exe, os.X_OK)
    assert [p.name for p in exe.parent.iterdir()] == [exe.name]  # no source or half-built file left
    package = Path(sa.__file__).parent
    assert sorted(p.name for p in package.iterdir() if p.suffix != ".pyc" and p.name != "__pycache__") == \
        ["__init__.py", "avr_harness.c", "c.py", "firmware.py", "gpsim.py", "record.py", "simavr.py"]


def test_missing_gpsim_names_the_debian_package(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    assert not gp.available()
    with pytest.raises(gp.GpsimError, match="install the Debian package gpsim"):
        gp.run_pic(hexfile("sample_hello.hex"), "pic16f877", 4_000_000)


# =========================================================================== PIC16 (gpsim)


@needs_gpsim
def test_pic_contacts_and_coils():
    """reg/tests/contacts.ld, PIC16F876 28-PDIP at 4 MHz. IO: Xa 2 = RA0, Xb 3 = RA1,
    Xc 4 = RA2, Xd 5 = RA3, Xe 6 = RA4, Yg 7 = RA5, Yf 11 = RC0, Yh 12 = RC1.
    Yf = Xa; Yg is set by Xb || Xc and reset by Xd && !Xe; Yh = !(Xd && !Xe)."""
    pins = {"Xa": "RA0", "Xb": "RA1", "Xc": "RA2", "Xd": "RA3", "Xe": "RA4"}
    steps = [  # (time_ms, changes)
        (0, {"Xa": 0, "Xb": 0, "Xc": 0, "Xd": 0, "Xe": 0}),
        (100, {"Xa": 1}), (200, {"Xa": 0}),
        (300, {"Xb": 1}), (350, {"Xb": 0}),
        (400, {"Xd": 1}),
        (500, {"Xe": 1}),
        (600, {"Xc": 1}), (650, {"Xc": 0}),
        (700, {"Xe": 0}),
        (800, {"Xd": 0}),
    ]
    inputs = [(t, pins[n], v) for t, ch in steps for n, v in ch.items()]
    run = gp.run_pic(hexfile("reg_tests_contacts.hex"), "Microchip PIC16F876 28-PDIP or 28-SOIC",
                     4_000_000, inputs=inputs, watch=["RC0", "RA5", "RC1"], until_ms=900)
    # reference model of the three rungs, cycle by cycle at the probe times
    state = {n: 0 for n in pins}
    yg = 0
    for t, changes in steps:
        state.update(changes)
        if state["Xb"] or state["Xc"]:
            yg = 1
        if state["Xd"] and not state["Xe"]:
            yg = 0
        yf, yh = state["Xa"], int(not (state["Xd"] and not state["Xe"]))
        probe = t + 40
        got = (run.level_at("RC0", probe), run.level_at("RA5", probe), run.level_at("RC1", probe))
        assert got == (yf, yg, yh), (t, dict(state), got)
    # every output change follows its input change within one PLC cycle
    change_times = [t for t, _ in steps]
    for t_edge, pin, _ in run.edges:
        if t_edge < SCAN * 2:
            continue  # the first cycle sets the initial outputs
        assert any(0 <= t_edge - t <= SCAN + 1 for t in change_times), (t_edge, pin)


@needs_gpsim
def test_pic_blink_modes():
    """sample/blink.ld, PIC16F877 40-PDIP at 4 MHz. IO: Xbutton 21 = RD2 (active low),
    Yled 30 = RD7. CTC Cwhich 4 counts presses and picks the pattern:
    0: Rfast (TOF 100 ms -> TON 100 ms -> /Rfast: 100 ms on, 100 ms off);
    1: Rslow (TON 100 ms -> TOF 1 s -> /Rslow: 100 ms on every 1.1 s); 3 (double click:
    a press within 500 ms of a release, TOF Tdblclk): steady on; 4: off; then 0 again."""
    presses = [(1000, 1050),                  # single press -> Cwhich 1
               (4000, 4050), (4200, 4250),    # double click -> Cwhich 3
               (6000, 6050),                  # -> Cwhich 4
               (8000, 8050)]                  # -> wraps to 0
    inputs = [(0, "RD2", 1)]
    for down, up in presses:
        inputs += [(down, "RD2", 0), (up, "RD2", 1)]
    run = gp.run_pic(hexfile("sample_blink.hex"), "Microchip PIC16F877 40-PDIP", 4_000_000,
                     inputs=inputs, watch=["RD7"], until_ms=9000)
    edges = run.pin_edges("RD7")

    def between(a, b):
        return [(t, v) for t, v in edges if a <= t < b]

    # mode 0: 100 ms on / 100 ms off, from the first cycle
    fast = between(0, 1000)
    assert_edges(fast, [(SCAN + 200 * k + d, v) for k in range(5) for d, v in ((0, 1), (100, 0))],
                 tol=1.0)
    # mode 1: 100 ms flashes, 1.1 s apart
    slow = between(1100, 3900)
    assert [v for _, v in slow] == [1, 0] * (len(slow) // 2) and len(slow) >= 4, slow
    for (on, _), (off, _) in zip(slow[::2], slow[1::2]):
        assert abs((off - on) - 100) <= 1.0, slow
    for (a, _), (b, _) in zip(slow[::2], slow[2::2]):
        assert abs((b - a) - 1100) <= SCAN + 1, slow
    # double click: steady on until the next press, then off until the one after
    assert_edges(between(3900, 8000), [(4000, 1), (6000, 0)], tol=SCAN + 1)
    assert run.level_at("RD7", 7900) == 0
    # back to mode 0
    again = between(8000, 9000)
    assert len(again) >= 8 and all(abs((b - a) - 100) <= 1.0
                                   for (a, _), (b, _) in zip(again, again[1:])), again


@needs_gpsim
def test_pic_adc_sent_over_serial():
    """sample/pic-adc.ld, PIC16F877 40-PDIP at 4 MHz, 2400 baud. IO: Xlimit 2 = RA0,
    Ain 3 = RA1 (AN1), Yled 22 = RD3. After "\\r\\nadc\\r\\n" it sends the ADC reading as three
    digits + CR LF, one character per Rosc period (100 ms)."""
    run = gp.run_pic(hexfile("sample_pic-adc.hex"), "PIC16F877", 4_000_000,
                     inputs=[(0, "RA0", 1), (3000, "RA0", 0)],
                     analog=[(0, "RA1", 2.5), (1600, "RA1", 1.0)],
                     watch=["RD3"], until_ms=3500)
    text = run.uart_bytes()
    assert text.startswith(b"\r\nadc\r\n"), text
    # (time of the line's LF, value)
    readings = [(run.uart[m.end() - 1][0], int(m.group(1)))
                for m in re.finditer(rb"(\d{3})\r\n", text)]
    first = [v for t, v in readings if t < 1600]
    later = [v for t, v in readings if t > 1600 + 600]   # a full line after the change
    assert first and later, readings
    assert all(abs(v - 2.5 / 5 * 1023) <= 2 for v in first), readings
    assert all(abs(v - 1.0 / 5 * 1023) <= 2 for v in later), readings
    # Yled = Rosc || !Xlimit would blink while Xlimit = 1, but LDmicro's READ_ADC writes
    # ADCON1 = 0x80 (every PORTA pin analog), so RA0 reads 0 and Yled stays on from the first
    # cycle: gpsim models the analog pins, and this is what the reference HEX does.
    assert_edges(run.pin_edges("RD3"), [(SCAN, 1)])


@needs_gpsim
def test_gpsim_errors(tmp_path):
    hex_path = hexfile("reg_tests_contacts.hex")
    with pytest.raises(gp.GpsimError, match="Unable to find processor"):
        gp.run_pic(hex_path, "p16f999", 4_000_000, until_ms=10)
    with pytest.raises(gp.GpsimError, match="porte"):   # the 16F876 has no PORTE
        gp.run_pic(hex_path, "p16f876", 4_000_000, watch=["RE1"], until_ms=10)
    with pytest.raises(gp.GpsimError, match="no HEX"):
        gp.run_pic(tmp_path / "missing.hex", "p16f876", 4_000_000, until_ms=10)
    assert gp.processor_name("Microchip PIC16F876 28-PDIP or 28-SOIC") == "p16f876"
    assert gp.processor_name("PIC16F877A") == "p16f877a"


@needs_gpsim
def test_gpsim_register_reads():
    run = gp.run_pic(hexfile("reg_tests_contacts.hex"), "p16f876", 4_000_000,
                     inputs=[(0, p, 0) for p in ("RA0", "RA1", "RA2", "RA3", "RA4")]
                     + [(100, "RA0", 1)],
                     reads=[(50, "portc"), (150, "portc"), (150, "trisc")], until_ms=200)
    assert run.reads == [(50.0, "portc", 0x02), (150.0, "portc", 0x03), (150.0, "trisc", 0xFC)]


@needs_gpsim
def test_gpsim_drives_a_port_b_input_against_its_weak_pull_up(tmp_path):
    """A switch to ground on RB4 with PORTB's weak pull-ups on: the pin reads 0
    every time it is driven low, not only before it was first high (the input
    modules are a switch, not a 10 kOhm resistor that leaves the pin between
    the thresholds)."""
    from builders import coil, contact, program

    import compiler

    built = compiler.build(program([contact("Xd"), coil("Ya")], mcu="Microchip PIC16F877 40-PDIP",
                                   pins={"Xd": "RB4", "Ya": "RC7"}, crystal_hz=20_000_000))
    hex_path = tmp_path / "follow.hex"
    built.write(hex_path)
    run = gp.run_pic(hex_path, "p16f877", 20_000_000, inputs=[(0, "RB4", 0), (55, "RB4", 1), (85, "RB4", 0)],
                     watch=["RC7"], until_ms=120)
    assert [level for _, level in run.pin_edges("RC7")] == [1, 0]
