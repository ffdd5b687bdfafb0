"""Peripherals of programs compiled for the enhanced mid-range parts, in
gpsim beside the simulator (pic16_harness.py): A/D readings (ANSELx,
ADCON1's clock select, GO_NOT_DONE), UART text sent and bytes received
(EUSART), PERSIST through the data EEPROM (EEADRL/EEDATL), on the PIC12F1840
and the PIC16F1824 (gpsim's p16f1825); SET PWM's duty and frequency on the
CCP pin; and the located errors: PERSIST on the PIC16F151x (no data
EEPROM), a clock the internal oscillator cannot make, a run of a part gpsim
has no model of; the corpus's PIC16 programs moved to both parts (slow)."""

from __future__ import annotations

from dataclasses import replace

import pytest
from builders import coil, contact, el, move, program
from pic16_harness import differential
from test_compiler_harness import Event, load
from test_pic16_compiler import CASES
from test_pic16_encoding import needs_gpsim
from test_pic16e_ldmicro import moved

import compiler
from compiler.errors import CompileError
from compiler.pic16.part import Part
from compiler.run import gpsim
from compiler.run.firmware import record
from compiler.run.record import FirmwareError

pytestmark = needs_gpsim

# not the MCLR pin RA3 for an input: gpsim 0.31 restarts these parts on its edges
PARTS = {"pic12f1840": {"Ain": "RA4", "Xa": "RA5", "Ya": "RA2", "Yb": "RA0"},
         "pic16f1824": {"Ain": "RC1", "Xa": "RA4", "Ya": "RC2", "Yb": "RA2"}}


def _pins(part: str, *names: str) -> dict[str, str]:
    return {name: PARTS[part][name] for name in names}


@pytest.mark.parametrize("part", sorted(PARTS))
def test_adc_readings_follow_the_simulator(part, tmp_path):
    prog = program([el("READ_ADC", name="Ain")], [el("GEQ", op1="Ain", op2="500"), coil("Ya")],
                   [el("GRT", op1="Ain", op2="900"), coil("Yb")], mcu=part,
                   pins=_pins(part, "Ain", "Ya", "Yb"), crystal_hz=16_000_000)
    events = [Event(0, "Ain", 100), Event(10, "Ain", 600), Event(20, "Ain", 1000), Event(30, "Ain", 0)]
    assert differential(prog, events, 40, tmp_path) == []


@pytest.mark.parametrize("part", sorted(PARTS))
def test_uart_bytes_received_and_sent_follow_the_simulator(part, tmp_path):
    prog = program([el("UART_RECV", var="vr")], [contact("Xa"), el("UART_SEND", var="vr")],
                   [el("EQU", op1="vr", op2="65"), coil("Ya")],
                   mcu=part, pins=_pins(part, "Xa", "Ya"), crystal_hz=16_000_000, baud=9600)
    events = [Event(0, "Xa", 1), Event(3, "uart", 65), Event(8, "uart", 66), Event(12, "Xa", 0)]
    assert differential(prog, events, 20, tmp_path) == []


@pytest.mark.parametrize("part", sorted(PARTS))
def test_persist_keeps_its_variable_in_the_eeprom(part, tmp_path):
    prog = program([el("PERSIST", var="kept")], [contact("Xa"), el("ADD", dest="kept", op1="kept", op2="1")],
                   [el("GEQ", op1="kept", op2="5"), coil("Ya")], mcu=part, pins=_pins(part, "Xa", "Ya"),
                   crystal_hz=16_000_000)
    events = [Event(0, "Xa", 1), Event(8, "Xa", 0)]
    assert differential(prog, events, 30, tmp_path) == []


@pytest.mark.parametrize("part,pin,port,bit", [("pic12f1840", "RA2", "porta", 2), ("pic16f1824", "RC5", "portc", 5),
                                               ("pic16f1824", "RC4", "portc", 4), ("pic16f1824", "RC3", "portc", 3),
                                               ("pic16f1824", "RC2", "portc", 2)])
def test_pwm_duty_and_frequency_on_the_ccp_pin(part, pin, port, bit, tmp_path):
    """The pin as CCP1 (or CCP2) drives it, sampled 400 times over 4 periods
    of 1 kHz; on the PIC16F1824 the CCP's steering puts it on RC4 (P1B) or RC2
    (P2B), LDmicro's other PWM pins, and the port's other pins stay still."""
    prog = program([move("duty", "30")], [el("SET_PWM", duty="duty", freq=1000, name="Ppwm")],
                   mcu=part, pins={"Ppwm": pin}, crystal_hz=16_000_000)
    build = compiler.build(prog)
    build.write(tmp_path / "pwm.hex")
    times = [20 + 4 * i / 400 for i in range(400)]
    run = gpsim.run_pic(tmp_path / "pwm.hex", Part.of(build.device).gpsim, 16_000_000,
                        reads=[(t, port) for t in times], until_ms=times[-1] + 1, timeout=120)
    levels = [value >> bit & 1 for _, _, value in run.reads]
    assert sum(1 for a, b in zip(levels, levels[1:]) if b > a) in (4, 5)
    assert abs(sum(levels) / len(levels) - 0.30) < 0.02
    assert len({value & ~(1 << bit) for _, _, value in run.reads}) == 1


@pytest.mark.parametrize("freq,scale", [(40000, 4), (8000, 5)])
@pytest.mark.parametrize("duty", [1, 30, 99])
def test_a_pwm_scale_of_four_or_five_needs_no_multiplication(freq, scale, duty, tmp_path):
    """40 kHz and 8 kHz at 16 MHz are periods of 100 and 125: a duty of 0..100
    makes 4 or 5 x duty tenths of a Timer2 count, written as the duty itself
    or shifted and added (LSLF, ADDWFC), not multiplied: CCPR1L and
    CCP1CON<5:4> hold them in gpsim."""
    prog = program([move("duty", str(duty))], [el("SET_PWM", duty="duty", freq=freq, name="Ppwm")],
                   mcu="pic16f1824", pins={"Ppwm": "RC5"}, crystal_hz=16_000_000)
    build = compiler.build(prog)
    assert "mul3" not in build.image.listing
    build.write(tmp_path / "pwm.hex")
    run = gpsim.run_pic(tmp_path / "pwm.hex", Part.of(build.device).gpsim, 16_000_000,
                        reads=[(5, "ccpr1l"), (5, "ccp1con")], until_ms=6, timeout=120)
    tenths = scale * duty
    assert [value for _, _, value in run.reads] == [tenths >> 2, (tenths & 3) << 4 | 0x0C]


def test_two_pwm_names_on_the_pins_of_one_ccp_are_a_located_error():
    second = el("SET_PWM", duty="70", freq=1000, name="Pb")
    prog = program([el("SET_PWM", duty="30", freq=1000, name="Pa")], [second], mcu="pic16f1824",
                   pins={"Pa": "RC5", "Pb": "RC4"}, crystal_hz=16_000_000)
    with pytest.raises(CompileError) as raised:
        compiler.build(prog)
    (found,) = raised.value.diagnostics
    assert found.code == "LD708" and "'Pa' and 'Pb' are both outputs of CCP1" in found.message
    assert found.span == second.span


@pytest.mark.parametrize("part", ["pic16f1512", "pic16f1516", "pic16f1527"])
def test_persist_without_a_data_eeprom_is_a_located_error(part):
    prog = program([el("PERSIST", var="kept")], mcu=part)
    with pytest.raises(CompileError) as raised:
        compiler.build(prog)
    (found,) = raised.value.diagnostics
    assert found.code == "LD705" and "has 0" in found.message and found.span is not None


def test_a_clock_the_internal_oscillator_cannot_make_is_refused():
    prog = program([contact("Xa"), coil("Ya")], mcu="pic12f1840", pins={"Xa": "RA3", "Ya": "RA5"},
                   crystal_hz=20_000_000)
    with pytest.raises(CompileError) as raised:
        compiler.build(prog)
    (found,) = raised.value.diagnostics
    assert found.code == "LD716" and "32, 16, 8, 4" in found.message and "20 MHz" in found.message


def test_running_a_part_gpsim_has_no_model_of_says_so():
    """`ladder test --on pic16` of a PIC16F1827 program: a stated reason, not gpsim's error."""
    prog = program([contact("Xa"), coil("Ya")], mcu="pic16f1827", pins={"Xa": "RB0", "Ya": "RB4"})
    with pytest.raises(FirmwareError, match="gpsim has no model of the PIC16F1827"):
        record("pic16", prog, [], 3, {"Ya"})


@pytest.mark.slow
@pytest.mark.parametrize("part", sorted(PARTS))
@pytest.mark.parametrize("path", sorted(CASES))
def test_corpus_programs_moved_to_the_part_follow_the_simulator(path, part, tmp_path):
    """test_pic16_compiler.py's corpus programs and stimuli, moved to the part
    as test_pic16e_ldmicro.py moves them, but not on the MCLR pin (gpsim
    restarts the part on its edges), at 16 MHz: at 4 MHz pic16-hw's scan (an
    EEPROM write waited for, a 32-bit division) runs past the point of the
    cycle where the harness reads the RAM. The PIC12F1840 has too few pins
    left for contacts.ld, pic-adc.ld, pic16-hw.ld and swatch1.ld (its UART
    takes two of its five)."""
    events, scans, _ = CASES[path]
    prog = moved(load(path), part, input_only=False)
    if prog is None:
        assert part == "pic12f1840" and path in ("reg/tests/contacts.ld", "sample/pic-adc.ld",
                                                 "reg/tests/pic16-hw.ld", "sample/swatch1.ld")
        return
    prog = replace(prog, settings=replace(prog.settings, crystal_hz=16_000_000))
    assert differential(prog, events, scans, tmp_path) == []


@pytest.mark.parametrize("hz", [4_000_000, 16_000_000])
def test_pwm_on_the_only_ccp_leaves_the_cycle_to_a_free_running_timer1(hz, tmp_path):
    """The PIC12F1840's one CCP makes PWM: Timer1 runs free for the cycle, and a timer, a count and
    the coil follow the simulator scan for scan."""
    prog = program([contact("Xa"), el("TON", name="Tdel", delay=50000), coil("Ya")],
                   [el("SET_PWM", duty="30", freq=1000, name="Pp")], [contact("Xa"), el("ADD", dest="n", op1="n", op2="1")],
                   mcu="pic12f1840", pins={"Xa": "RA4", "Ya": "RA5", "Pp": "RA2"}, crystal_hz=hz)
    assert differential(prog, [Event(2, "Xa", 1), Event(30, "Xa", 0)], 40, tmp_path) == []


@pytest.mark.parametrize("fsr1", [False, True])
def test_outputs_on_two_ports_follow_the_simulator(fsr1, tmp_path):
    """The latch the scan uses most is reached through FSR1/INDF1, the other one by its bank: set,
    reset and read back (a contact on an output), on both ports; a program that writes FSR1L
    itself (`#0x86`, its bank-1 address) keeps both latches banked."""
    rungs = [[contact("Xa"), coil("Ya")], [contact("Ya"), coil("Yb", "S")], [contact("Xb"), coil("Yb", "R")],
             [contact("Yb"), coil("Yc")], [contact("Xb", negated=1), contact("Yc"), coil("Yd")]]
    if fsr1:
        rungs.append([contact("Xa"), move("#0x86", "5")])
    prog = program(*rungs, mcu="pic16f1824", pins={"Xa": "RA4", "Xb": "RC4", "Ya": "RA2", "Yb": "RC0", "Yc": "RC1",
                                                     "Yd": "RA5"}, crystal_hz=16_000_000)
    events = [Event(1, "Xa", 1), Event(4, "Xa", 0), Event(6, "Xb", 1), Event(9, "Xb", 0), Event(11, "Xa", 1)]
    assert differential(prog, events, 16, tmp_path) == []


def test_look_up_tables_reached_by_brw_follow_the_simulator(tmp_path):
    """A table (LDmicro's at most 64 entries) is jumped into by BRW from the
    index's low byte: two of them read at every index in gpsim beside the
    simulator, one of the largest size."""
    long, short = [(i * 7 + i // 8) % 4 for i in range(64)], [1, 3, 0, 2, 3, 1]
    rungs = [[el("ADD", dest="vi", op1="vi", op2="1")], [el("GEQ", op1="vi", op2=str(len(long))), move("vi", 0)],
             [el("ADD", dest="vs", op1="vs", op2="1")], [el("GEQ", op1="vs", op2=str(len(short))), move("vs", 0)],
             [el("LOOK_UP_TABLE", dest="vt", index="vi", values=tuple(map(str, long)))],
             [el("LOOK_UP_TABLE", dest="vu", index="vs", values=tuple(map(str, short)))],
             [el("EQU", op1="vt", op2="1"), coil("Ya")], [el("EQU", op1="vt", op2="2"), coil("Yb")],
             [el("EQU", op1="vu", op2="1"), coil("Yc")], [el("EQU", op1="vu", op2="3"), coil("Yd")]]
    prog = program(*rungs, mcu="pic16f1824", pins={"Ya": "RA2", "Yb": "RC0", "Yc": "RC1", "Yd": "RA5"},
                   crystal_hz=16_000_000)
    assert compiler.build(prog).image.listing.count("\tbrw") == 2
    assert differential(prog, [], 2 * len(long), tmp_path) == []
