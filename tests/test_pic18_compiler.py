"""The PIC18 back end end to end: the PIC16 corpus programs and the oracle
programs of tests/pic16_programs moved to the PIC18F4520 (40 pins) or the
PIC18F2520 (28 pins, the PIC16F876's footprint), compiled, run in gpsim and
compared with the simulator on every name after every scan
(pic16_harness.py); the peripherals on their pins; both parts reassembled
by gpasm; the scan-time budget against the scans gpsim measures; programs
that do not fit."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
import test_pic16_compiler as pic16
from builders import coil, contact, el, par, program
from pic16_harness import differential, erase_eeprom
from test_compiler_budget import TIGHT, _pic_inputs, _sound, measure_pic
from test_compiler_harness import Event, load
from test_pic16_compiler import BLINK, CASES, ORACLES, SCANS_BEFORE_A_FAULT, _oracle_events, _program

import compiler
from compiler.errors import CompileError
from compiler.pic18.part import Part
from compiler.run import gpsim
from lang.loader import load_path
from lang.model import PinAssignment

pytestmark = pytest.mark.slow

PIC18_PINS = {"Xa": "RD0", "Xb": "RD1", "Xc": "RD2", "Ya": "RB0", "Yb": "RB1", "Yc": "RB2", "Yd": "RB3"}


def moved(part: str) -> str:
    """The PIC18 with the same package: pins by number mean the same port bits."""
    return "pic18f2520" if part.startswith(("pic16f876", "Microchip PIC16F876", "p16f876")) else "pic18f4520"


@pytest.mark.parametrize("path", sorted(CASES))
def test_corpus_program_follows_the_simulator(path, tmp_path):
    events, scans, adapt = CASES[path]
    program_ = load(path)
    if adapt:
        program_ = adapt(program_)
    assert differential(program_, events, scans, tmp_path, moved(program_.settings.mcu)) == []


# the oracle programs of the 40- and 28-pin PIC16s (the others' pins by number mean nothing on these)
MOVED_ORACLES = sorted(p.stem for p in ORACLES.glob("p16f87[67]_*.ld")
                       if p.stem not in {"p16f877_arith", "p16f877_sleep", "p16f877_watchdog",
                                         "p16f877_target_extras", "p16f877_uart_recv"})


@pytest.mark.parametrize("name", MOVED_ORACLES)
def test_oracle_program_follows_the_simulator(name, tmp_path):
    """Every instruction LDmicro's PIC16 back end compiles (the oracle set's
    reasons for leaving a few out are test_pic16_compiler's)."""
    program_, _ = load_path(ORACLES / f"{name}.ld")
    stimulus = json.loads((ORACLES / f"{name}.json").read_text())
    if stimulus.get("reset"):
        stimulus["until_ms"] = min(stimulus["until_ms"], stimulus["reset"][0])
    scans = int(stimulus["until_ms"] * 1000 // program_.settings.cycle_us) - 1
    scans = min(scans, SCANS_BEFORE_A_FAULT.get(name, scans))
    assert differential(program_, _oracle_events(program_, stimulus), scans, tmp_path, moved(name)) == []


@pytest.mark.parametrize("part", ["pic18f4520", "pic18f2520"])
def test_blink_by_port_bits_runs_and_gpasm_agrees(part, tmp_path):
    from intelhex import IntelHex

    program_ = load("sample/blink.ld")
    program_.pins["Xbutton"] = PinAssignment("Xbutton", "RB0")
    program_.pins["Yled"] = PinAssignment("Yled", "RB1")
    assert differential(program_, BLINK, 200, tmp_path, part) == []
    compiler.build(program_, part).write(tmp_path / "p.hex")
    subprocess.run(["gpasm", "-o", str(tmp_path / "g.hex"), str(tmp_path / "p.asm")], check=True, capture_output=True)
    assert IntelHex(str(tmp_path / "p.hex")).todict() == IntelHex(str(tmp_path / "g.hex")).todict()


# --- peripherals on their pins -------------------------------------------------------------------

PIC18F4520 = "MICRO=Microchip PIC18F4520 40-PDIP"
# test_pic16_compiler's programs on the PIC18F4520 (the same pins by number)
PWM_LD = pic16.PWM_LD.replace("MICRO=Microchip PIC16F877 40-PDIP", PIC18F4520)
# a rising edge of Xbump adds one: the EEPROM is written back
PERSIST_LD = pic16.PERSIST_LD.replace("MICRO=Microchip PIC16F877 40-PDIP", PIC18F4520).replace(
    "    Yseven at 19 0 0\n", "    Yseven at 19 0 0\n    Xbump at 33 0 0\n") + """RUNG
    CONTACTS Xbump 0 0
    OSR
    ADD kept kept 1
END
"""


@pytest.mark.parametrize("freq,pin,bit,duty", [(1000, 17, 2, "duty"), (5000, 17, 2, "duty"), (10000, 16, 1, "duty"),
                                              (5000, 16, 1, "30")])
def test_pwm_duty_and_frequency_on_the_ccp_pin(freq, pin, bit, duty, tmp_path):
    """CCP1 (RC2, the enhanced module in single-output mode) and CCP2 (RC1),
    sampled 400 times over 4 periods; the cycle moves to the other CCP; a
    literal duty is worked out by the compiler."""
    build = compiler.build(_program(PWM_LD.format(freq=freq, duty=duty).replace("Ppwm at 17", f"Ppwm at {pin}")))
    build.write(tmp_path / "pwm.hex")
    period_ms = 1000 / freq
    times = [20 + 4 * period_ms * i / 400 for i in range(400)]
    run = gpsim.run_pic(tmp_path / "pwm.hex", "p18f4520", 20_000_000, inputs=[(0, "RB0", 1)],
                        reads=[(t, "portc") for t in times], until_ms=times[-1] + 1, timeout=120)
    levels = [value >> bit & 1 for _, _, value in run.reads]
    rises = sum(1 for a, b in zip(levels, levels[1:]) if b > a)
    assert rises in (4, 5)
    assert abs(sum(levels) / len(levels) - 0.30) < 0.02


@pytest.mark.parametrize("part,pin,clock", [("pic18f4520", "RB0", 40_000_000), ("pic18f2520", "RB2", 16_000_000)])
def test_adc_channels_on_portb_follow_the_simulator(part, pin, clock, tmp_path):
    """AN12 (RB0) and AN8 (RB2), past LDmicro's AN0-AN7: ADCON1's PCFG group
    that reaches them makes them analog (gpsim reads 0 on a pin left digital);
    at 40 MHz the converter runs at Fosc/64 (1.6 us)."""
    prog = program([el("READ_ADC", name="Ain")], [el("GEQ", op1="Ain", op2="500"), coil("Ya")],
                   [el("GRT", op1="Ain", op2="900"), coil("Yb")], mcu=part,
                   pins={"Ain": pin, "Ya": "RC0", "Yb": "RC1"}, crystal_hz=clock)
    events = [Event(0, "Ain", 100), Event(10, "Ain", 600), Event(20, "Ain", 1000), Event(30, "Ain", 0)]
    assert differential(prog, events, 40, tmp_path) == []


def test_persist_reads_the_eeprom_at_start_and_writes_it_back(tmp_path):
    """A value in the data EEPROM (preloaded through the HEX at 0xF00000, as
    a previous run would have left it) is the variable's value from the first
    scan; a change is written back (read again in gpsim's EEPROM)."""
    from intelhex import IntelHex

    build = compiler.build(_program(PERSIST_LD))
    path = tmp_path / "persist.hex"
    build.write(path)
    part = Part.of(build.device)
    erase_eeprom(path, part.eeprom, part.eeprom_hex)
    image = IntelHex(str(path))
    image[0xF00000], image[0xF00001] = 7, 0  # kept = 7, little-endian
    image.write_hex_file(str(path))
    run = gpsim.run_pic(path, "p18f4520", 4_000_000, inputs=[(0, "RB0", 0), (60, "RB0", 1)], watch=["RD0"],
                        reads=[(150, "eeadr")], until_ms=200, timeout=60)
    assert run.level_at("RD0", 45) == 1
    assert run.level_at("RD0", 150) == 0  # kept = 8
    edges = run.pin_edges("RD0")
    assert [v for _, v in edges] == [1, 0]


def test_a_cycle_longer_than_timer1_counts_runs_it_free(tmp_path):
    """0.6 s at 4 MHz is past Timer1's 65,536 counts with its largest
    prescaler: it runs free, and the cycle-duty pin rises every cycle."""
    prog = program([contact("Xa"), coil("Yb")], mcu="pic18f4520", cycle_us=600_000, crystal_hz=4_000_000,
                   pins={"Xa": "RA0", "Yb": "RB1", "YPlcCycleDuty": "RB2"}, cycle_duty=True)
    compiler.build(prog).write(tmp_path / "slow.hex")
    run = gpsim.run_pic(tmp_path / "slow.hex", "p18f4520", 4_000_000, inputs=[(0, "RA0", 0)], watch=["RB2"],
                        until_ms=3100, timeout=120)
    rises = [t for t, v in run.pin_edges("RB2") if v]
    assert len(rises) == 6
    assert all(abs(t - rises[0] - 600 * k) < 0.5 for k, t in enumerate(rises))


def test_a_40_mhz_clock_through_the_pll_keeps_the_cycle(tmp_path):
    """At 40 MHz (a 10 MHz crystal and the PLL) the cycle-duty pin rises
    every millisecond. gpsim 0.31 does not model the PLL: it runs the part at
    the frequency it is given, the 40 MHz the PLL makes."""
    prog = program([contact("Xa"), coil("Yb")], mcu="pic18f4520", cycle_us=1000, crystal_hz=40_000_000,
                   pins={"Xa": "RA0", "Yb": "RB1", "YPlcCycleDuty": "RB2"}, cycle_duty=True)
    build = compiler.build(prog)
    build.write(tmp_path / "pll.hex")
    assert build.image.segments[0x300000][1] & 0x0F == 0b0110  # CONFIG1H: HSPLL
    run = gpsim.run_pic(tmp_path / "pll.hex", "p18f4520", 40_000_000, inputs=[(0, "RA0", 0)], watch=["RB2"],
                        until_ms=20, timeout=60)
    rises = [t for t, v in run.pin_edges("RB2") if v]
    # within the wait loop's jitter of a few instruction cycles (0.1 us each), and gpsim's special event
    # trigger, which restarts Timer1 one count early on the PIC16 and PIC18 models alike (999 of 1000)
    assert len(rises) >= 19
    assert all(abs(t - rises[0] - k) < 0.01 for k, t in enumerate(rises))


def test_the_watchdog_a_programmer_enables_is_cleared_every_scan(tmp_path):
    """The configuration keeps the watchdog off, as LDmicro's HI-TECH C
    output does (WDTDIS); enabled at its shortest period (CONFIG2H = WDTEN,
    1:1 postscaler: 4 ms) under a 10 ms cycle, the wait loop's and the
    DELAYs' CLRWDT keep it from resetting the part: Yboot pulses once and
    the scans go on. (gpsim resets the part when a LOCK stops the scans; its
    runner cannot follow a run through a reset.)"""
    from intelhex import IntelHex

    program_, _ = load_path(ORACLES / "p16f877_watchdog.ld")
    build = compiler.build(program_, "pic18f4520")
    assert not build.image.segments[0x300000][3] & 1  # CONFIG2H: WDTEN off
    path = tmp_path / "wdt.hex"
    build.write(path)
    image = IntelHex(str(path))
    image[0x300003] = 0x01
    image.write_hex_file(str(path))
    run = gpsim.run_pic(path, "p18f4520", 4_000_000, inputs=[(0, "RB0", 0), (0, "RB1", 0), (300, "RB1", 1),
                                                             (400, "RB1", 0)], watch=["RD0", "RD1"], until_ms=480)
    assert [(round(t, -1), v) for t, v in run.pin_edges("RD0")] == [(0, 1), (210, 0)]
    assert len(run.pin_edges("RD1")) >= 45  # Yalive toggles every 10 ms scan


# --- the scan-time budget --------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(TIGHT))
def test_worst_case_is_sound_and_tight_on_loop_free_programs(name, tmp_path):
    """No scan gpsim measures is longer than the bound, and the bound is
    within 1.25 times the longest."""
    build, measured = measure_pic(TIGHT[name]("pic18f4520", PIC18_PINS), _pic_inputs(80, 10), 800, tmp_path)
    assert build.budget.loops == (), "not loop-free"
    assert _sound(build, measured) <= 1.25


def test_worst_case_covers_blink_and_a_program_of_loops(tmp_path):
    blink = load("sample/blink.ld")
    _sound(*measure_pic(compiler.retarget(blink, compiler.target_device(blink, "pic18f4520")),
                        [(0, "RD2", 1), (300, "RD2", 0), (320, "RD2", 1), (900, "RD2", 0)], 2000, tmp_path))
    loops = program(
        [contact("Xa"), par([el("ADD", dest="n", op1="n", op2="12345")], [el("DIV", dest="q", op1="n", op2="7")],
                            [el("SHL", dest="s", op1="n", op2="k")], [el("BIN2BCD", dest="b", src="q")],
                            [el("MUL", dest="m", op1="n", op2="q")])],
        [contact("Xb"), par([el("ADD", dest="k", op1="k", op2="1")], [el("MOD", dest="k", op1="k", op2="31")])],
        mcu="pic18f4520", pins=PIC18_PINS, crystal_hz=4_000_000, sizes={"n": 4, "q": 4, "s": 4, "k": 2, "b": 4, "m": 4})
    build, measured = measure_pic(loops, _pic_inputs(100, 10), 1000, tmp_path)
    assert "a 32-bit division, one bit a pass" in {w.what for w in build.budget.loops}
    _sound(build, measured)


@pytest.mark.parametrize("path", ["sample/serial.ld", "sample/swatch1.ld", "sample/pic-adc.ld"])
def test_worst_case_covers_tables_the_uart_and_the_converter(path, tmp_path):
    """Formatted strings (TBLRD tables, divisions), UART waits, an A/D
    conversion: no scan measured over 3 s is longer than the bound."""
    moved_program = load(path)
    moved_program = compiler.retarget(moved_program, compiler.target_device(moved_program, "pic18f4520"))
    _sound(*measure_pic(moved_program, [], 3000, tmp_path))


# --- what does not fit ------------------------------------------------------------------------------

def test_a_program_too_large_for_program_memory_is_located_with_the_figures():
    rungs = [[contact("Xa"), par([el("MUL", dest=f"p{i}", op1=f"p{i}", op2=f"q{i % 7}")],
                                 [el("DIV", dest=f"q{i % 7}", op1=f"p{i}", op2="3")],
                                 [el("GRT", op1=f"p{i}", op2=f"q{(i + 3) % 7}"), coil("Ya")])] for i in range(300)]
    sizes = {**{f"p{i}": 4 for i in range(300)}, **{f"q{i}": 4 for i in range(7)}}
    with pytest.raises(CompileError) as found:
        compiler.build(program(*rungs, mcu="pic18f4520", pins=PIC18_PINS, sizes=sizes))
    (problem,) = found.value.diagnostics
    assert problem.code == "LD703"
    assert "bytes of program memory; the PIC18F4520 has 32768" in problem.message


def test_variables_beyond_the_ram_are_located_with_the_figures():
    rungs = [[contact("Xa"), el("ADD", dest=f"v{i}", op1=f"v{i}", op2="1")] for i in range(400)]
    with pytest.raises(CompileError) as found:
        compiler.build(program(*rungs, mcu="pic18f4520", pins=PIC18_PINS, sizes={f"v{i}": 4 for i in range(400)}))
    (problem,) = found.value.diagnostics
    assert problem.code == "LD704"
    assert "banks of 256 addresses; the PIC18F4520 has 1536" in problem.message


# --- scenarios on the PIC18 image --------------------------------------------------------------------

SCENARIOS = Path(__file__).resolve().parent / "scenarios"


def test_the_pic16_scenarios_pass_on_the_program_moved_to_the_pic18f4520(tmp_path, capsys):
    """`ladder test --on pic18`: blink, serial (bytes received through a
    usart module on RX) and the timers, their programs' MICRO made the
    PIC18F4520 (the same pins by number)."""
    from ladder.cli import main
    from lang.sim.scenario import parse_scenarios

    files = []
    for name in ("blink", "serial", "pic16-timers"):
        scenario = SCENARIOS / f"{name}.scn"
        text = scenario.read_text()
        source = (SCENARIOS / parse_scenarios(text, str(scenario))[0].program).resolve()
        program_text = source.read_text(encoding="cp1252")
        assert "MICRO=Microchip PIC16F877 40-PDIP" in program_text
        moved_program = tmp_path / source.name
        moved_program.write_text(program_text.replace("MICRO=Microchip PIC16F877 40-PDIP",
                                                      "MICRO=Microchip PIC18F4520 40-PDIP"), encoding="cp1252")
        lines = [f"program {moved_program.name}" if line.startswith("program ") else line for line in text.splitlines()]
        (tmp_path / scenario.name).write_text("\n".join(lines) + "\n")
        files.append(str(tmp_path / scenario.name))
    status = main(["test", "--on", "pic18", *files])
    out = capsys.readouterr().out
    assert status == 0, out
    assert " 0 failed" in out


def test_a_program_past_the_reach_of_bra_runs_with_goto_and_call(tmp_path):
    """Rungs of arithmetic and comparisons over 2,048 words: the jumps back to
    the scan and the calls of the division routine are GOTO and CALL; in
    gpsim the program follows the simulator scan for scan."""
    from test_compiler_harness import Event

    rungs = [[contact("Xa" if i % 2 else "Xb"),
              par([el("ADD", dest=f"v{i}", op1=f"v{i}", op2="3")], [el("GRT", op1=f"v{i}", op2="100"), coil("Ya")],
                  [el("EQU", op1=f"v{(i + 7) % 30}", op2=f"v{i}"), el("DIV", dest=f"m{i}", op1=f"v{i}", op2="3")])]
             for i in range(60)]
    built = program(*rungs, mcu="pic18f4520", pins={"Xa": "RD0", "Xb": "RD1", "Ya": "RB0"}, crystal_hz=20_000_000)
    build = compiler.build(built)
    assert len(build.image.words) > 2048
    listing = build.image.listing
    assert "\tgoto\tscan" in listing and "\tcall\tdivmod" in listing
    events = [Event(0, "Xa", 1), Event(0, "Xb", 0), Event(10, "Xb", 1), Event(20, "Xa", 0), Event(30, "Xa", 1)]
    assert differential(built, events, 60, tmp_path) == []


@pytest.mark.parametrize("part,mcu", [("p18f4520", "pic18f4520"), ("p16f877", "Microchip PIC16F877 40-PDIP")])
def test_a_delay_lasts_its_time(part, mcu, tmp_path):
    """DELAY 5 ms (a constant) and DELAY by a variable holding TIME2DELAY's
    count for 3 ms, between an output set and cleared: the pin's high time in
    gpsim is the delay's, within one loop pass and the instructions around it
    (the PIC18's loop ends in one BNZ: its count has its own cycles)."""
    prog = program([contact("Xa"), par([coil("Ya", "S")], [el("DELAY", delay=5000)], [coil("Ya", "R")])],
                   [contact("Xa"), par([coil("Yb", "S")], [el("TIME2DELAY", name="d", delay=3000)],
                                       [el("DELAY", delay="d")], [coil("Yb", "R")])],
                   mcu=mcu, pins={"Xa": "RD0", "Ya": "RB0", "Yb": "RB1"}, crystal_hz=4_000_000, sizes={"d": 4})
    compiler.build(prog).write(tmp_path / "d.hex")
    run = gpsim.run_pic(tmp_path / "d.hex", part, 4_000_000, inputs=[(0, "RD0", 1)], watch=["RB0", "RB1"],
                        until_ms=100, timeout=60)
    for pin, ms in (("RB0", 5.0), ("RB1", 3.0)):
        edges = run.pin_edges(pin)
        highs = [fall - rise for (rise, up), (fall, _) in zip(edges, edges[1:]) if up]
        assert highs and all(abs(high - ms) < 0.03 for high in highs), (pin, highs)
