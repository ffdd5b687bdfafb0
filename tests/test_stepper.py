"""STEPPER: LDmicro's acceleration tables, the simulated steps, and the
compiled image in simavr scan for scan beside the simulator and edge for
edge beside LDmicro's own AVR HEX (the PIC16 image against LDmicro's is
tests/pic16_programs/p16f877_stepper in test_pic16_oracle.py)."""

from __future__ import annotations

import re

import pytest
from builders import coil, contact, el, move, program
from ldmicro_oracle import ldmicro_compile
from pic16_harness import differential as pic_differential
from test_compiler_encoding import needs_avr_gcc, reassemble
from test_compiler_harness import Event, differential, needs_simavr
from test_pic10_compiler import needs_gpsim

import compiler
from lang.ldfile import write_ld
from lang.semantics.acceleration import steps
from lang.sim import Simulator

# (size, graph, period: 0 for a variable) -> the table LDmicro 5.4.1.1's C
# output declares for it (`const unsigned char Ui_sa[9] = {...}`)
LDMICROS_TABLES = {
    (10, 1, 3): (19, 8, 6, 5, 4, 4, 4, 3, 3),
    (40, 1, 2): (25, 10, 8, 7, 6, 5, 5, 5, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 2, 2),
    (8, 2, 0): (96, 56, 47, 42, 39, 36, 34, 33, 32),
    (30, 4, 0): (116, 30, 21, 17, 14, 12, 11, 10, 9, 9, 8, 8, 7, 7, 6, 6, 6, 6, 6, 5, 5, 5, 5, 5, 5, 4, 4),
    (30, 5, 7): (255, 66, 47, 37, 31, 27, 24, 22, 20, 19, 18, 17, 16, 15, 14, 14, 15, 16, 17, 18, 19, 20, 22, 24,
                 27, 31, 37, 47, 66, 255, 7),
    (30, 6, 1): (1, 1),
}
# LDmicro's shift after multiplying by a variable period (`Ui_CsbP = Ui_CsbP >> 5;`)
LDMICROS_SHIFTS = {(8, 2, 0): 5, (30, 4, 0): 2, (100, 3, 0): 4}


@pytest.mark.parametrize("key", sorted(LDMICROS_TABLES))
def test_acceleration_table_is_ldmicros(key):
    assert steps(*key).table == LDMICROS_TABLES[key]


@pytest.mark.parametrize("key", sorted(LDMICROS_SHIFTS))
def test_variable_period_shift_is_ldmicros(key):
    assert steps(*key).shift == LDMICROS_SHIFTS[key]


def _run(stepper, scans: int, before=(), sizes=None):
    """Each scan's (steps left, output power) with the input on, and the
    scans in which a step was made (steps left went down)."""
    sim = Simulator(program(*before, [contact("Xgo"), stepper, coil("Ybusy")], sizes=sizes))
    left = f"C{stepper.args['name']}Dec"
    made, rows, last = [], [], int(stepper.args["max"])  # the first scan loads max
    sim.set_input("Xgo", 1)
    for scan in range(scans):
        sim.step()
        if sim.value(left) < (rows[-1][0] if rows else last):
            made.append(scan)
        rows.append((sim.value(left), sim.value("Ybusy")))
    return rows, made


def test_every_scan_without_a_table_makes_max_steps_then_stops():
    rows, made = _run(el("STEPPER", name="s", max="5", p="1", size=0, graph=1, coil="Ya"), 8)
    assert made == [0, 1, 2, 3, 4]
    assert rows == [(4, 1), (3, 1), (2, 1), (1, 1), (0, 1), (0, 0), (0, 0), (0, 0)]


def test_every_p_scans_without_a_curve():
    """graph 0: no table; the first step comes in the scan that starts the
    run, then one every p scans; power passes until the scan after the last."""
    rows, made = _run(el("STEPPER", name="s", max="3", p="4", size=10, graph=0, coil="Ya"), 12)
    assert made == [0, 4, 8]
    assert [busy for _, busy in rows] == [1] * 9 + [0] * 3


def test_steps_follow_the_table_up_and_back_down():
    """With a literal period the waits between steps are LDmicro's table read
    forwards, the full-speed period (its last entry) in the middle, and the
    table backwards at the end, indexed by the steps left before the step
    is counted: so down to entry 2, the two slowest waits are not repeated."""
    table = steps(10, 1, 3).table
    rows, made = _run(el("STEPPER", name="s", max="30", p="3", size=10, graph=1, coil="Ya"), 400)
    gaps = [b - a for a, b in zip(made, made[1:])]
    assert len(made) == 30
    assert gaps[:len(table)] == list(table)
    assert gaps[len(table):-(len(table) - 2)] == [table[-1]] * (29 - 2 * len(table) + 2)
    assert gaps[-(len(table) - 2):] == list(table[:1:-1])
    assert rows[-1] == (0, 0)


def test_a_variable_period_scales_the_table():
    """With a variable period the table is the curve scaled by 2**shift; each
    wait is the entry times the period, shifted back."""
    ramp = steps(8, 2, 0)
    _, made = _run(el("STEPPER", name="s", max="40", p="per", size=8, graph=2, coil="Ya"), 400,
                   before=[[move("per", "3")]], sizes={"per": 2})
    gaps = [b - a for a, b in zip(made, made[1:])]
    assert len(made) == 40
    waits = [v * 3 >> ramp.shift for v in ramp.table]
    assert gaps[:len(waits)] == waits
    assert gaps[-(len(waits) - 2):] == waits[:1:-1]


def test_restart_only_once_the_run_is_over():
    sim = Simulator(program([contact("Xgo"), el("STEPPER", name="s", max="3", p="2", size=0, graph=0, coil="Ya")]))
    pattern = [1, 0, 1, 0, 0, 0, 0, 0, 1]
    lefts = []
    for level in pattern:
        sim.set_input("Xgo", level)
        sim.step()
        lefts.append(sim.value("CsDec"))
    # the second rising edge comes while steps remain: no reload; the third reloads
    assert lefts == [2, 2, 1, 1, 0, 0, 0, 0, 2]


# --- compiled --------------------------------------------------------------------------------

AVR = "Atmel AVR ATmega328 28-PDIP"
PINS = {"Xgo": "PD2", "Ya": "PB0", "Yb": "PB1", "Yc": "PB2", "Yd": "PB3", "Ybusy": "PB4"}


def _four_forms():
    """The four forms LDmicro compiles: along the table, along the table
    scaled by a variable period, every p scans, every scan."""
    return program([contact("Xgo"), el("STEPPER", name="sa", max="25", p="2", size=6, graph=1, coil="Ya"),
                    coil("Ybusy")],
                   [contact("Xgo"), el("STEPPER", name="sb", max="40", p="per", size=30, graph=4, coil="Yb")],
                   [contact("Xgo"), el("STEPPER", name="sc", max="6", p="3", size=0, graph=1, coil="Yc")],
                   [contact("Xgo"), el("STEPPER", name="sd", max="5", p="1", size=0, graph=2, coil="Yd")],
                   [move("per", "3")],
                   mcu=AVR, pins=PINS, sizes={"per": 2}, cycle_us=1000, crystal_hz=8_000_000)


EVENTS = [Event(0, "Xgo", 0), Event(5, "Xgo", 1), Event(60, "Xgo", 0), Event(700, "Xgo", 1)]


@needs_simavr
@pytest.mark.slow
def test_compiled_steps_follow_the_simulator(tmp_path):
    """The step counters (C<name>Dec, Inc, P) and outputs after every scan."""
    assert differential(_four_forms(), EVENTS, 1400, tmp_path) == []


def _small(mcu: str, pins: dict[str, str]):
    """A table form and the scaled form, for the 6-pin parts."""
    return program([contact("Xgo"), el("STEPPER", name="sa", max="12", p="2", size=6, graph=1, coil="Ya")],
                   [contact("Xgo"), el("STEPPER", name="sb", max="9", p="per", size=5, graph=4, coil="Yb")],
                   [move("per", "3")],
                   mcu=mcu, pins=pins, sizes={"per": 1}, crystal_hz=4_000_000)


SMALL_EVENTS = [Event(0, "Xgo", 0), Event(2, "Xgo", 1), Event(20, "Xgo", 0), Event(150, "Xgo", 1)]


@needs_avr_gcc
def test_the_attiny10_image_reassembles(tmp_path):
    """simavr has no ATtiny10 core: its image is checked by avr-gcc for that
    core (no instruction the reduced core lacks, the same words)."""
    build = compiler.build(_small("attiny10", {"Xgo": "PB0", "Ya": "PB1", "Yb": "PB2"}))
    assert reassemble(build.image.listing, "attiny10", tmp_path) == build.image.program_bytes()


@needs_gpsim
@pytest.mark.slow
@pytest.mark.parametrize("mcu, pins", [
    ("pic10f202", {"Xgo": "GP3", "Ya": "GP1", "Yb": "GP2"}),  # the PIC10F200's 16 bytes hold one STEPPER (LD704)
    ("pic12f1840", {"Xgo": "RA5", "Ya": "RA2", "Yb": "RA0"}),  # the enhanced mid-range core
])
def test_the_small_parts_step_as_the_simulator(mcu, pins, tmp_path):
    assert pic_differential(_small(mcu, pins), SMALL_EVENTS, 300, tmp_path) == []


@needs_simavr
@pytest.mark.ldmicro
def test_same_step_pulses_as_ldmicros_avr_hex(tmp_path):
    """Each step is a pulse within the scan, in both images: the same edges on
    every output, each within a scan (the scaled form with a period of 3,
    which LDmicro's PIC16 SHR gets wrong, is right in its AVR code)."""
    from test_avr_parts_ldmicro import ldmicros_hex
    from test_compiler_corpus import same_edges_as_ldmicro

    prog = _four_forms()
    same_edges_as_ldmicro(prog, ldmicros_hex(prog, tmp_path), EVENTS, 1400, tmp_path)


@pytest.mark.ldmicro
def test_tables_are_those_of_ldmicros_c(tmp_path):
    """LDmicro's C output declares each STEPPER's table: ours are the same
    for every curve, literal and variable periods."""
    cases = [(n, g, p) for g in range(1, 7) for n, p in ((5, 1), (37, 3), (100, 0), (64, 11))]
    rungs = [[contact("Xgo"), el("STEPPER", name=f"s{i}", max="500", p=str(p) if p else "per", size=n, graph=g,
                                 coil="Ya")] for i, (n, g, p) in enumerate(cases)]
    prog = program(*rungs, sizes={"per": 2}, compiler="ANSIC")
    source = tmp_path / "program.ld"
    source.write_text(write_ld(prog, "0.2"), encoding="latin-1")
    ldmicro_compile(source, tmp_path / "program.c", check=True)
    c = (tmp_path / "program.c").read_text(encoding="latin-1")
    for i, key in enumerate(cases):
        found = re.search(rf"^const unsigned \w+ Ui_s{i}\[\d+\] = \{{([^}}]*)\}};", c, re.M)
        assert found, f"no table for {key}"
        assert steps(*key).table == tuple(int(v) for v in found.group(1).split(",")), key
