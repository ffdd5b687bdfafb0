"""Raw register access (RSFR, WSFR, SSFR, CSFR, TSFR, TCSFR): the simulator's
register file a user sets like an A/D reading, the AVR images in simavr
(a port's pin driven, an input pin tested, registers read into variables,
scan for scan against the simulator), LDmicro's own HEX of the same program
(the same pin edges), and the check on constant addresses."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from builders import coil, contact, el, move, none, one, program
from ldmicro_oracle import ldmicro_compile
from test_compiler_harness import differential, needs_simavr

import compiler
from compiler.run import simavr as sa
from compiler.run.record import Event
from ladder.cli import main
from lang.checks import check_program
from lang.ldfile import write_ld
from lang.sim import Simulator

M328 = "Atmel AVR ATmega328 28-PDIP"
PORTB, DDRB, PIND, GPIOR0, GPIOR1, GPIOR2 = 0x25, 0x24, 0x29, 0x3E, 0x4A, 0x4B  # the ATmega328P's data addresses


def sfr(kind: str, first, second) -> object:
    """An SFR element with its operands in LDmicro's order (`RSFR dest sfr`,
    `WSFR sfr src`, `SSFR mask sfr`...)."""
    names = {"RSFR": ("dest", "sfr"), "WSFR": ("sfr", "src")}.get(kind, ("mask", "sfr"))
    return el(kind, **{names[0]: str(first), names[1]: str(second)})


# --- the simulator ------------------------------------------------------------------------------

def test_a_read_copies_the_register_the_user_set():
    sim = Simulator(program([sfr("RSFR", "v", PIND)]))
    sim.step()
    assert sim.value("v") == 0  # a register never written reads 0
    sim.set("#0x29", 0xA5)
    sim.step()
    assert sim.value("v") == 0xA5  # 0 to 255, whatever dest's size


def test_writes_sets_and_clears_change_the_register_and_the_tests_read_it():
    sim = Simulator(program(
        [sfr("WSFR", GPIOR0, 0x10F)],  # the low byte
        [sfr("SSFR", 0x30, GPIOR0)],
        [sfr("CSFR", "m", GPIOR0)],
        [sfr("TSFR", 0x34, GPIOR0), coil("Yall")],
        [sfr("TSFR", 0x41, GPIOR0), coil("Ysome")],
        [sfr("TCSFR", 0xC0, GPIOR0), coil("Ynone")],
    ))
    sim.set_variable("m", 0x103)  # the mask is its low byte
    sim.step()
    assert sim.register(GPIOR0) == 0x3C
    assert (sim.value("Yall"), sim.value("Ysome"), sim.value("Ynone")) == (1, 0, 1)


def test_an_address_in_a_variable_reaches_the_same_register():
    sim = Simulator(program([move("a", GPIOR1)], [sfr("WSFR", "a", 7)], [sfr("RSFR", "v", GPIOR1)],
                            [sfr("RSFR", "w", "a")]))
    sim.step()
    assert (sim.register(GPIOR1), sim.value("v"), sim.value("w")) == (7, 7, 7)


def test_nothing_happens_without_power():
    sim = Simulator(program([contact("Xa"), sfr("WSFR", PORTB, 1)], [contact("Xa"), sfr("RSFR", "v", PIND)]))
    sim.set("#41", 9)
    sim.step()
    assert (sim.register(PORTB), sim.value("v")) == (0, 0)


def test_a_register_value_must_be_a_byte():
    sim = Simulator(program([sfr("RSFR", "v", PIND)]))
    with pytest.raises(ValueError, match="out of range 0..255"):
        sim.set("#0x29", 256)


def test_ladder_sim_sets_a_register(tmp_path, capsys):
    path = tmp_path / "read.ld"
    path.write_bytes(write_ld(program([sfr("RSFR", "v", PIND)], mcu=M328)).encode("cp1252"))
    assert main(["sim", str(path), "--for", "30ms", "--set", "#0x29=4@10ms", "--watch", "v"]) == 0
    assert capsys.readouterr().out.splitlines() == ["10 v 4"]  # changes only


def test_ladder_sim_watches_a_register(tmp_path, capsys):
    path = tmp_path / "write.ld"
    path.write_bytes(write_ld(program([contact("Xa"), sfr("WSFR", PORTB, 0x20)], mcu=M328)).encode("cp1252"))
    assert main(["sim", str(path), "--for", "30ms", "--set", "Xa=1@10ms", "--watch", "#0x25"]) == 0
    assert capsys.readouterr().out.splitlines() == ["10 #0x25 32"]


def test_a_scenario_sets_and_expects_registers(tmp_path, capsys):
    (tmp_path / "copy.ld").write_bytes(write_ld(program(
        [sfr("RSFR", "v", PIND)], [contact("Xa"), sfr("WSFR", PORTB, "v")], mcu=M328)).encode("cp1252"))
    (tmp_path / "copy.scn").write_text(
        "# `#` before a digit names a register, elsewhere it starts a comment\n"
        "program copy.ld\n"
        "at 0 set #0x29 = 5  # PIND\n"
        "at 20 ms set Xa = 1\n"
        "at 10 ms expect #0x25 = 0\n"
        "at 30 ms expect #0x25 = 5 and v = 5\n")
    assert main(["test", str(tmp_path / "copy.scn")]) == 0, capsys.readouterr().out


def test_the_editors_simulation_sets_a_register():
    from ide.analysis import Analysis
    from ide.session import Simulation
    from lang.loader import TEXT_KIND, parse
    from lang.textform.writer import render_program

    text = render_program(program([sfr("RSFR", "v", PIND)], mcu=M328))
    session = Simulation(Analysis(TEXT_KIND, text, *parse(text, TEXT_KIND)))
    session.set("#0x29", 6)
    session.step(1)
    assert session.value("v") == 6


# --- the checks ----------------------------------------------------------------------------------

@pytest.mark.parametrize("address, why", [
    (5, "data addresses 0x20 to 0x8FF; 0x00 to 0x1F are the working registers"),
    (0x900, "data addresses 0x20 to 0x8FF"),
])
def test_a_constant_address_the_part_does_not_have_is_an_error(address, why):
    hit = one(program([sfr("WSFR", address, 1)], mcu=M328), "LD702")
    assert hit.severity == "error" and why in hit.message


def test_a_register_or_ram_address_is_not_refused():
    none(program([sfr("WSFR", PORTB, 1)], [sfr("RSFR", "v", 0x8FF)], mcu=M328), "LD702")
    # the ATtiny10's I/O registers start at data address 0, its RAM ends at 0x5F
    tiny = "Atmel AVR ATtiny10 6-Pin packages"
    none(program([sfr("WSFR", 0x02, 1)], mcu=tiny), "LD702")
    assert "data addresses 0x00 to 0x5F)" in one(program([sfr("WSFR", 0x60, 1)], mcu=tiny), "LD702").message


@pytest.mark.parametrize("mcu", ["Microchip PIC16F877 40-PDIP", None])
def test_the_pic_and_c_back_ends_do_not_compile_it_as_ldmicros_do_not(mcu):
    family = None if mcu else "c"
    found = [d for d in check_program(program([sfr("SSFR", 1, PORTB)], mcu=mcu), family=family) if d.code == "LD501"]
    assert len(found) == 1


# --- compiled, in simavr ---------------------------------------------------------------------------

def _pins_program():
    """PB5 follows Xa through SSFR/CSFR on PORTB (DDRB written by WSFR); YPD2
    follows the pin PD2, which no name of the program has, through TSFR on PIND."""
    return program(
        [sfr("WSFR", DDRB, 0x3F)],
        [move("m", 0x20)],
        [contact("Xa"), sfr("SSFR", "m", PORTB)],
        [contact("Xa", negated=1), sfr("CSFR", "m", PORTB)],
        [move("four", 4)],
        [sfr("TSFR", "four", PIND), coil("YPD2")],
        mcu=M328, pins={"Xa": 6, "YPD2": 13}, crystal_hz=16_000_000,
    )


CYCLE_MS = 10
PIN_STIMULUS = [(0.0, "D4", 0), (0.0, "D2", 0), (25.0, "D4", 1), (55.0, "D2", 1), (75.0, "D4", 0), (95.0, "D2", 0)]


def _levels(edges, pin: str) -> list[int]:
    return [v for _, v in edges[pin]]


def _pin_edges(hex_path: Path) -> dict:
    run = sa.simulate_avr(hex_path, "atmega328p", 16_000_000, until_ms=120, inputs=PIN_STIMULUS,
                          watch=["B5", "D7"])
    return {pin: run.pin_edges_ms(pin) for pin in ("B5", "D7")}


@needs_simavr
@pytest.mark.slow
def test_set_and_clear_drive_a_port_pin_and_a_test_follows_an_input_pin(tmp_path):
    build = compiler.build(_pins_program())
    build.write(tmp_path / "sfr.hex")
    edges = _pin_edges(tmp_path / "sfr.hex")
    # each edge within one scan of its cause
    assert _levels(edges, "B5") == [1, 0] and _levels(edges, "D7") == [1, 0]
    rise, fall = (t for t, _ in edges["B5"])
    assert 25 <= rise <= 25 + CYCLE_MS and 75 <= fall <= 75 + CYCLE_MS
    rise, fall = (t for t, _ in edges["D7"])
    assert 55 <= rise <= 55 + CYCLE_MS and 95 <= fall <= 95 + CYCLE_MS


@needs_simavr
@pytest.mark.slow
def test_registers_read_into_variables_agree_with_the_simulator_scan_for_scan(tmp_path):
    """On registers that hold what is written (the GPIORs), where the
    simulator's model is the hardware: constant and variable addresses."""
    prog = program(
        [contact("Xa"), el("ADD", dest="count", op1="count", op2="1")],
        [sfr("WSFR", GPIOR1, "count")],
        [sfr("RSFR", "v", GPIOR1)],
        [move("a", GPIOR2)],
        [sfr("WSFR", "a", "count")],
        [sfr("SSFR", 0x80, "a")],
        [sfr("CSFR", "one", "a")],
        [sfr("RSFR", "w", "a")],
        [sfr("TSFR", 0x82, GPIOR2), coil("Rboth")],
        [sfr("TCSFR", "one", GPIOR1), coil("Reven")],
        [move("one", 1)],
        mcu=M328, pins={"Xa": 6}, crystal_hz=16_000_000,
    )
    events = [Event(0, "Xa", 1), Event(20, "Xa", 0), Event(25, "Xa", 1)]
    assert differential(prog, events, 40, tmp_path) == []


# --- against LDmicro's own HEX ------------------------------------------------------------------------



def _ldmicro(prog, folder: Path) -> subprocess.CompletedProcess:
    source = folder / "program.ld"
    source.write_bytes(write_ld(prog).replace("\n", "\r\n").encode("cp1252"))
    return ldmicro_compile(source, folder / "ldmicro.hex")


@needs_simavr
@pytest.mark.ldmicro
def test_the_same_pin_edges_as_ldmicros_hex(tmp_path):
    prog = _pins_program()
    done = _ldmicro(prog, tmp_path)
    assert "Compiled okay" in done.stdout, done.stdout + done.stderr
    compiler.build(prog).write(tmp_path / "ours.hex")
    ours, theirs = _pin_edges(tmp_path / "ours.hex"), _pin_edges(tmp_path / "ldmicro.hex")
    for pin in ("B5", "D7"):
        assert _levels(ours, pin) == _levels(theirs, pin), pin
        for (t_ours, _), (t_theirs, _) in zip(ours[pin], theirs[pin]):
            # LDmicro's first scan starts one cycle later than ours
            assert abs(t_ours - t_theirs) <= CYCLE_MS + 0.1, (pin, ours[pin], theirs[pin])


@pytest.mark.ldmicro
def test_ldmicro_refuses_a_set_with_a_constant_mask_and_address_which_we_compile(tmp_path):
    """LDmicro 5.4.1.1's AVR back end looks up a variable for the constant
    forms of SSFR, CSFR, TSFR and TCSFR (INT_SET_SFR_LITERAL_L...), which have
    none: "Empty variable name". Ours builds them."""
    prog = program([sfr("SSFR", 0x20, PORTB)], mcu=M328)
    done = _ldmicro(prog, tmp_path)
    assert "Empty variable name" in done.stdout + done.stderr
    assert compiler.build(prog).device.part == "atmega328p"


@pytest.mark.ldmicro
@pytest.mark.parametrize("settings, output", [("MICRO=Microchip PIC16F877 40-PDIP", "out.hex"),
                                              ("COMPILER=ANSIC", "out.c")])
def test_ldmicros_pic16_and_c_back_ends_refuse_it(settings, output, tmp_path):
    """Why these families keep LD501: LDmicro's pic16.cpp and ansic.cpp have
    no case for the SFR operations ("INT_1063" is INT_SET_SFR_LITERAL)."""
    source = tmp_path / "program.ld"
    source.write_bytes(f"LDmicro0.2\r\n{settings}\r\nCYCLE=10000 us at Timer1, YPlcCycleDuty:0\r\nCRYSTAL=4000000 Hz\r\n"
                       "\r\nPROGRAM\r\nRUNG 1\r\n  SSFR m 0x25\r\nEND\r\n".encode("cp1252"))
    done = ldmicro_compile(source, tmp_path / output)
    assert "Compile error" in done.stdout + done.stderr and "INT_1063" in done.stdout + done.stderr


@needs_simavr
@pytest.mark.ldmicro
def test_ldmicros_clear_with_an_address_variable_and_a_constant_mask_keeps_the_mask(tmp_path):
    """LDmicro 5.4.1.1's INT_CLEAR_SFR_VARIABLE_L complements r0, not the
    mask it loaded into r28, then ANDs the register with the mask: CSFR 32 a
    leaves bit 5 alone and clears the others. Ours clears bit 5."""
    prog = program(
        [sfr("WSFR", DDRB, 0x3F)],
        [move("a", PORTB)],
        [contact("Xa"), sfr("WSFR", "a", 0x21)],
        [contact("Xa", negated=1), sfr("CSFR", 0x20, "a")],
        mcu=M328, pins={"Xa": 6}, crystal_hz=16_000_000,
    )
    done = _ldmicro(prog, tmp_path)
    assert "Compiled okay" in done.stdout, done.stdout + done.stderr
    compiler.build(prog).write(tmp_path / "ours.hex")
    stimulus = [(0.0, "D4", 1), (45.0, "D4", 0)]

    def levels(hex_path: Path) -> tuple[int, int]:
        run = sa.simulate_avr(hex_path, "atmega328p", 16_000_000, until_ms=80, inputs=stimulus, watch=["B0", "B5"])
        return run.level_at("B0", 79), run.level_at("B5", 79)

    assert levels(tmp_path / "ours.hex") == (1, 0)
    assert levels(tmp_path / "ldmicro.hex") == (0, 1)
