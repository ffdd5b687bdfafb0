"""The baseline PIC10F200/202 (compiler/pic10/): the device files against
gputils' header (p10f200.inc) and linker script (10f200_g.lkr) and LDmicro's
pins; gpsim has both processors; images reassembled by gpasm to the same
words; small programs (contacts, timers, counters, arithmetic through the
lowered ADDLW/SUBLW, the multiplication and division routines, a table, a
GOSUB) run in gpsim against the simulator scan for scan; the refusals of
programs that do not fit (program memory, RAM, the two-level stack) and of
peripherals the parts lack, located with the figures; the scan-time budget
against the scans gpsim measures. The slow step draws 300 random programs
that fit."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest
from builders import coil, contact, counter, el, par, program, timer
from hypothesis import HealthCheck, assume, given, settings
from pic16_harness import differential
from test_compiler_budget import _sound, measure_pic
from test_compiler_harness import IN_CI, Event
from test_compiler_random import PIC16_PERIPHERALS, Board, cases
from test_pic16_compiler import SLEEP_LD
from test_pic16_parts import GPUTILS, hex_words, needs_gputils

import compiler
from compiler.errors import FLASH_FULL, RAM_FULL, CompileError
from compiler.pic10 import flow
from compiler.pic16.part import Part
from compiler.run import gpsim
from lang.devices import find_device
from lang.families import FAMILIES

PARTS = ("pic10f200", "pic10f202")
PINS = {"Xa": "GP3", "Xb": "GP0", "Ya": "GP1", "Yb": "GP2"}

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


def facts(part: str) -> dict:
    return find_device(part).data["pic10"]


def _header(processor: str) -> dict[str, dict[str, int]]:
    """Section name ("Register Files", "STATUS Bits", "CONFIG Options") -> its EQUs."""
    sections: dict[str, dict[str, int]] = {}
    current: dict[str, int] | None = None
    for line in (GPUTILS / "header" / f"{processor}.inc").read_text().splitlines():
        if line.startswith(";====="):
            current = None
        m = re.match(r"^;-----\s+(.+?)\s+-{3,}", line)
        if m:
            current = sections.setdefault(m.group(1), {})
            continue
        m = re.match(r"^(\w+)\s+EQU\s+H'([0-9A-Fa-f]+)'", line)
        if m and current is not None:
            current[m.group(1)] = int(m.group(2), 16)
        if m and m.group(1) == "_CONFIG":
            sections["config address"] = {"_CONFIG": int(m.group(2), 16)}
    return sections


def _linker(processor: str) -> dict[str, range]:
    found = {}
    for line in (GPUTILS / "lkr" / f"{processor[1:]}_g.lkr").read_text().splitlines():
        m = re.match(r"^(?:CODEPAGE|DATABANK)\s+NAME=(\S+)\s+START=0x([0-9A-F]+)\s+END=0x([0-9A-F]+)", line, re.I)
        if m:
            found[m.group(1)] = range(int(m.group(2), 16), int(m.group(3), 16) + 1)
    return found


# --- the parts ------------------------------------------------------------------------------------


@needs_gputils
@pytest.mark.parametrize("part", PARTS)
def test_part_facts_match_gputils(part):
    data = facts(part)
    header = _header(data["processor"])
    assert data["registers"] == header["Register Files"]
    assert {f"{register} Bits" for register in data["bits"]} == {name for name in header if name.endswith(" Bits")}
    for register, named in data["bits"].items():
        assert named == header[f"{register} Bits"], register
    script = _linker(data["processor"])
    assert data["flash_words"] == len(script["page"])
    assert [range(first, last + 1) for first, last in data["ram"]] == [script["gprs"]]
    assert find_device(part).memory["ram"] == len(script["gprs"])
    (word,) = data["config"]["words"]
    assert word["address"] == header["config address"]["_CONFIG"]
    options = header["CONFIG Options"]
    value = 0xFFF
    for field in data["config"]["fields"].values():
        assert options[field["symbol"]] | field["mask"] == 0xFFF  # the symbol clears only its own bits
        assert options[field["symbol"]] & field["mask"] == field["value"]
        value &= options[field["symbol"]]
    assert word["value"] == value == 0xFEB  # watchdog off, no code protection, GP3 an input (LDmicro's)
    # GP3 is the reset input when MCLRE is set (_MCLRE_ON), as the reserved pins say for LD413
    (reset,) = find_device(part).data["reserved_pins"]["GP3"]
    mclre = data["config"]["fields"]["MCLRE"]["mask"]
    assert (reset["field"], reset["mask"], reset["values"]) == ("MCLRE", mclre, [options["_MCLRE_ON"] & mclre])


def test_pins_are_ldmicros():
    """mcutable.h's Pic6Pin_SOT23: GP0 at 1, GP1 at 3, GP2 at 4, GP3 (input only) at 6."""
    for part in PARTS:
        device = find_device(f"Microchip {part.upper()} 6-SOT")
        assert device.part == part and FAMILIES["pic10"].parts == PARTS
        assert {pin.name: pin.number for pin in device.io_pins()} == {"GP0": 1, "GP1": 3, "GP2": 4, "GP3": 6}
        assert device.pin("GP3").input_only and not (device.adc or device.pwm or device.uart)
        assert find_device(part[3:]) == device


@needs_gpsim
@pytest.mark.parametrize("part", PARTS)
def test_gpsim_models_the_part(part):
    run = subprocess.run(["gpsim", "-i", "-p", facts(part)["gpsim"]], input="quit\n", capture_output=True,
                         text=True, timeout=30)
    assert run.returncode == 0 and "Unable" not in run.stdout + run.stderr


def test_ladder_parts_lists_both_with_build_yes(capsys):
    from ladder.cli import main

    main(["parts"])
    out = capsys.readouterr().out
    for title in ("PIC10F200", "PIC10F202"):
        (line,) = [line for line in out.splitlines() if f"Microchip {title} 6-SOT" in line]
        assert "yes" in line.split()


@pytest.mark.parametrize("part", PARTS)
def test_build_takes_the_lower_case_target_name(part, tmp_path, capsys):
    from ladder.cli import main

    source = Path(__file__).resolve().parent / "pic10_programs" / "p10f200_basic.ld"
    assert main(["build", str(source), "--target", part, "-o", str(tmp_path / "p.hex")]) == 0
    assert capsys.readouterr().out.startswith(f"{part.upper()}: flash ")
    assert (tmp_path / "p.asm").read_text().count(f"processor p{part[3:]}") == 1


# --- programs ---------------------------------------------------------------------------------------


def _logic(mcu: str):
    return program(
        [par([contact("Xa")], [contact("Ya")]), contact("Xb", 1), coil("Ya")],
        [contact("Xa"), timer("TON", "Ton", 50_000), timer("TOF", "Toff", 30_000), coil("Yb")],
        [contact("Xb"), el("OSR"), counter("CTU", "Cup", 5)],
        mcu=mcu, pins=PINS, crystal_hz=4_000_000)


def _arithmetic(mcu: str):
    """16-bit sums and comparisons (ADDLW, SUBLW written with baseline
    instructions), a multiplication, a signed division."""
    return program(
        [contact("Xb"), el("OSR"), el("ADD", dest="s", op1="s", op2="301")],
        [el("GEQ", op1="s", op2="1200"), coil("Ya")],
        [contact("Xa"), par([el("MUL", dest="p", op1="s", op2="3")], [el("DIV", dest="q", op1="p", op2="-7")])],
        [el("LES", op1="q", op2="-100"), coil("Yb")],
        mcu=mcu, pins=PINS, sizes={"s": 2, "p": 2, "q": 2}, crystal_hz=4_000_000)


def _table_and_gosub(mcu: str):
    """A LOOK_UP_TABLE (a computed jump in the first 256 words) and a GOSUB."""
    return program(
        [contact("Xb"), el("OSR"), el("ADD", dest="i", op1="i", op2="1")],
        [el("GEQ", op1="i", op2="5"), move_zero("i")],
        [el("LOOK_UP_TABLE", dest="v", index="i", values=[3, 1, 4, 1, 5])],
        [el("GRT", op1="v", op2="2"), coil("Ya")],
        [contact("Xa"), el("GOSUB", label="blink")],
        [el("SUBPROG", label="blink")],
        [el("OSC"), coil("Yb")],
        [el("ENDSUB", label="blink")],
        mcu=mcu, pins=PINS, sizes={"i": 1, "v": 1}, crystal_hz=4_000_000)


def _comparisons(mcu: str):
    """Signed comparisons of 8- and 16-bit variables with constants of either
    sign (a SUBWF and a skip on the sign bit, or a chain of two skips), and
    equality tests of one variable against several constants in a row (W
    kept between them)."""
    return program(
        [contact("Xa"), contact("Xb"), el("OSR"), par([el("ADD", dest="b", op1="b", op2="29")],
                                       [el("SUB", dest="s", op1="s", op2="301")])],
        [el("GEQ", op1="b", op2="-3"), coil("Ya")],
        [par([el("LES", op1="b", op2="50")], [el("GRT", op1="s", op2="-700")]), coil("Rx")],
        # b takes 29 k mod 256 in turn: 58, -111 and 5 at the 2nd, 5th and 9th rising edge of Xb
        [par([el("EQU", op1="b", op2="58")], [el("EQU", op1="b", op2="-111")], [el("EQU", op1="b", op2="5")]),
         contact("Rx"), coil("Yb")],
        # a comparison whose jump folds into a chain of two skips on C and the sign, for each sign of c
        [el("GEQ", op1="b", op2="-3"), el("ADD", dest="n", op1="n", op2="7")],
        [el("LES", op1="b", op2="5"), el("ADD", dest="m", op1="m", op2="3")],
        # counts only their elements write are compared unsigned; one a MOVE makes negative, or sets to
        # 127 (a CTC then adds 1 before its test), is not
        [contact("Xb"), counter("CTC", "Cc", 3), timer("TON", "Tup", 30_000), coil("Rc")],
        [contact("Xb"), counter("CTC", "Cn", 4), coil("Rn")],
        [contact("Xa"), el("OSF"), el("MOVE", dest="Cn", src="-20")],
        [contact("Xb"), counter("CTC", "Cw", 2), coil("Rw")],
        [contact("Xa"), el("OSF"), el("MOVE", dest="Cw", src="127")],
        mcu=mcu, pins=PINS, sizes={"b": 1, "s": 2, "n": 1, "m": 1}, crystal_hz=4_000_000)


def _branches(mcu: str):
    """Rungs of nested parallel branches, contacts and comparisons, which the
    optimiser evaluates by jumps (compiler/optimise.py: the rung-state bits
    become tests, a branch that holds goes straight to the coil): the
    count c runs through 0..7 at every other scan while Xa and Xb change at
    every third and every scan, so every path of each rung is taken."""
    return program(
        [contact("Xb"), el("OSR"), el("ADD", dest="c", op1="c", op2="1")],
        [el("GEQ", op1="c", op2="8"), move_zero("c")],
        [par([contact("Xa"), contact("Rb", 1)], [el("EQU", op1="c", op2="3"), par([contact("Xb")],
                                                                                [el("GRT", op1="c", op2="5")])]),
         contact("Ra", 1), coil("Ya")],
        [par([contact("Ya")], [contact("Xa", 1), el("LES", op1="c", op2="2")]), contact("Xb", 1),
         par([coil("Yb")], [coil("Rb", "/")])],
        [contact("Xa"), par([contact("Rb")], [el("LES", op1="c", op2="4")]), par([coil("Ra", "S")],
                                                                               [contact("Yb"), coil("Rc")])],
        [par([contact("Rc")], [contact("Xb")]), par([contact("Ya", 1), el("NEQ", op1="c", op2="6")], [contact("Xa")]),
         coil("Ra", "R")],
        # a branch's one-shot whose edge bit is written on the path to the coil (a jump there is a target)
        [par([contact("Rd")], [el("OSR")]), coil("Rd")],
        mcu=mcu, pins=PINS, sizes={"c": 1}, crystal_hz=4_000_000)


def move_zero(name: str):
    return el("MOVE", dest=name, src="0")


PROGRAMS = {"logic": _logic, "arithmetic": _arithmetic, "table and gosub": _table_and_gosub,
            "comparisons": _comparisons, "branches": _branches}
# the arithmetic's division needs 9 scratch bytes beside its 10: more than the PIC10F200's 16
CASES = [(name, part) for name in sorted(PROGRAMS) for part in PARTS if (name, part) != ("arithmetic", "pic10f200")]
STIMULUS = [Event(0, "Xa", 1), *(Event(s, "Xb", s % 2) for s in range(1, 70)), Event(40, "Xa", 0),
            Event(55, "Xa", 1)]
# the branches' every combination of Xa, Xb and c: Xa changes at every third scan
STIMULI = {"branches": ([*(Event(s, "Xa", s // 3 % 2) for s in range(0, 100, 3)),
                         *(Event(s, "Xb", s % 2) for s in range(1, 100))], 100)}


@needs_gpsim
@pytest.mark.parametrize("name, part", CASES)
def test_program_follows_the_simulator(name, part, tmp_path):
    events, scans = STIMULI.get(name, (STIMULUS, 70))
    assert differential(PROGRAMS[name](part), events, scans, tmp_path) == []


@needs_gputils
@pytest.mark.parametrize("name, part", CASES)
def test_listing_reassembles_to_the_same_words_and_every_word_decodes(name, part, tmp_path):
    build = compiler.build(PROGRAMS[name](part))
    build.write(tmp_path / "p.hex")
    run = subprocess.run(["gpasm", "-o", str(tmp_path / "re.hex"), str(tmp_path / "p.asm")], capture_output=True,
                         text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    assert hex_words(tmp_path / "re.hex") == hex_words(tmp_path / "p.hex")
    words = build.image.words
    assert len(words) < facts(part)["flash_words"]  # the calibration word is left alone
    assert all(flow.instruction_at(words, address, build.device) is not None for address in range(len(words)))


# --- SLEEP ---------------------------------------------------------------------------------------------

WATCHDOG_ON = ", ConfigurationWord(s):0xFEF"  # LDmicro's word 0xFEB with WDTE set


def _sleep_hex(folder: Path, config: str = "") -> Path:
    from lang.loader import LD_KIND, parse

    text = SLEEP_LD.format(micro="Microchip PIC10F200 6-SOT", sleep=1, alive=4, timer="Timer0", config=config)
    prog, diagnostics = parse(text, LD_KIND)
    assert not [d for d in diagnostics if d.severity == "error"], diagnostics
    compiler.build(prog).write(folder / "sleep.hex")
    return folder / "sleep.hex"


def _scans_at(edges: list[float], start: float) -> bool:
    return all(abs(t - start - 10 * k) < 0.2 for k, t in enumerate(edges))


@needs_gpsim
def test_sleep_ends_the_scans_until_a_pin_change_restarts_the_program(tmp_path):
    """Yalive (GP2) toggles every scan until the scan that sees Xsleep (GP0)
    at 60 ms; then nothing while the pin stays high; its fall at 120 ms wakes
    the part with a reset: the start-up clears the outputs and the scans
    start again from there."""
    run = gpsim.run_pic(_sleep_hex(tmp_path), "p10f200", 4_000_000,
                        inputs=[(0, "GP0", 0), (55, "GP0", 1), (120, "GP0", 0)], watch=["GP2"],
                        until_ms=200, timeout=60)
    edges = run.pin_edges("GP2")
    before = [t for t, _ in edges if t < 120]
    assert len(before) == 7 and _scans_at(before, 0)  # the scans at 0 .. 60 ms
    reset, *after = [(t, level) for t, level in edges if t >= 120]
    assert reset[1] == 0 and reset[0] < 120.02  # the reset's start-up clears GPIO
    assert len(after) == 8 and _scans_at([t for t, _ in after], 120)


@needs_gpsim
def test_a_watchdog_reset_in_sleep_sleeps_again(tmp_path):
    """With the watchdog on, its time-out in SLEEP resets the part and the
    start-up sends it back to sleep (LDmicro's "SLEEP trap"): after the
    sleep at 60 ms, only each reset's start-up writes GPIO (outputs low), no
    scan runs. gpsim
    starts the p10f200 with TO and PD cleared (the part sets both at
    power-on), as after a watchdog wake-up: the script sets them first. A
    gpsim run ends at a watchdog reset, so the script runs on after each."""
    hex_path = _sleep_hex(tmp_path, WATCHDOG_ON)
    script = "\n".join([
        "processor p10f200", f"load {hex_path}", "frequency 4000000", "module library libgpsim_modules",
        "module load pullup xsleep", "xsleep.resistance = 100", "node n_xsleep", "attach n_xsleep xsleep.pin gpio0",
        "status = 0x18", f"log on {tmp_path / 'run.log'}", "log w gpio", "xsleep.voltage = 0",
        "break c 55000", "run", "xsleep.voltage = 5", "break c 300000", *["run"] * 9, "quit", ""])
    (tmp_path / "script.stc").write_text(script)
    out = subprocess.run(["gpsim", "-i", "-I", str(tmp_path / "script.stc")], stdin=subprocess.DEVNULL,
                         capture_output=True, text=True, errors="replace", timeout=60).stdout
    writes = [(cycle / 1000, value) for cycle, register, value in gpsim.parse_log((tmp_path / "run.log").read_text())
              if register == "gpio"]
    asleep = [(t, value) for t, value in writes if 61 < t < 300]
    assert out.count("Reset on Watch Dog Timer expire") >= len(asleep) >= 5  # one each 36 ms or so
    assert not any(value & 0b100 for _, value in asleep)  # only the start-up's CLRF GPIO: no scan sets Yalive


# --- what does not fit ---------------------------------------------------------------------------------


def _refusal(prog) -> tuple[str, str]:
    with pytest.raises(CompileError) as found:
        compiler.build(prog)
    (problem,) = [d for d in found.value.diagnostics if d.severity == "error"]
    return problem.code, problem.message


def test_a_program_too_large_for_program_memory_is_refused_with_the_figures():
    rungs = [[contact("Xa"), el("ADD", dest="v", op1="v", op2=str(i))] for i in range(90)]
    code, message = _refusal(program(*rungs, mcu="pic10f200", pins=PINS, sizes={"v": 2}))
    assert code == FLASH_FULL
    assert re.search(r"the program needs \d+ words of program memory; the PIC10F200 has 255 \(its last word keeps "
                     r"the oscillator calibration\)", message)


def test_tables_beyond_the_first_256_words_are_refused_with_the_address():
    """Five tables of 60 entries: the fifth ends past word 255, where a computed jump cannot reach."""
    rungs = [[contact("Xa"), el("LOOK_UP_TABLE", dest="v", index="i", values=[k + j for j in range(60)])]
             for k in range(5)]
    code, message = _refusal(program(*rungs, mcu="pic10f202", pins=PINS, sizes={"i": 1, "v": 1}))
    assert code == FLASH_FULL
    assert re.fullmatch(r"'table5_data' reaches word \d+: a CALL and a table's jump reach only the first 256 words "
                        r"of the PIC10F202", message)


def test_variables_beyond_the_ram_are_refused_with_the_figures():
    rungs = [[contact("Xa"), el("ADD", dest=f"v{i}", op1=f"v{i}", op2="1")] for i in range(7)]
    code, message = _refusal(program(*rungs, mcu="pic10f200", pins=PINS, sizes={f"v{i}": 2 for i in range(7)}))
    assert code == RAM_FULL and message.endswith("the PIC10F200 has 16")
    # the same fits the PIC10F202's 24 bytes
    compiler.build(program(*rungs, mcu="pic10f202", pins=PINS, sizes={f"v{i}": 2 for i in range(7)}))


def test_calls_deeper_than_the_two_level_stack_are_refused_at_the_gosub():
    """A signed division calls the unsigned one: inside a GOSUB that is three return addresses."""
    prog = program(
        [contact("Xa"), el("GOSUB", label="work")],
        [el("SUBPROG", label="work")],
        [el("DIV", dest="q", op1="q", op2="-3")],
        [el("ENDSUB", label="work")],
        mcu="pic10f202", pins=PINS, sizes={"q": 2})
    with pytest.raises(CompileError) as found:
        compiler.build(prog)
    (problem,) = found.value.diagnostics
    assert problem.code == RAM_FULL and problem.span is not None and problem.span.line == 0
    assert "3 return addresses at once; the PIC10F202's hardware stack holds 2" in problem.message
    assert problem.message.startswith("the program calls the subroutine at rung 3, which calls divmod2, which calls "
                                      "udivmod2")


@pytest.mark.parametrize("rung, code", [
    ([contact("Xa"), el("READ_ADC", name="Ain", refs=0)], "LD502"),
    ([contact("Xa"), el("UART_SEND", var="v", bytes=1, wait=0)], "LD503"),
    ([contact("Xa"), el("PERSIST", var="v")], "LD705"),
])
def test_a_peripheral_the_part_lacks_is_refused_at_its_element(rung, code):
    with pytest.raises(CompileError) as found:
        compiler.build(program(rung, mcu="pic10f200", pins=PINS, sizes={"v": 1}))
    problem = next(d for d in found.value.diagnostics if d.code == code)
    assert problem.span is not None and problem.span.line == 0


def test_a_pwm_output_is_refused_at_its_element():
    """LD504 at SET PWM (and LD405 at its pin)."""
    with pytest.raises(CompileError) as found:
        compiler.build(program([contact("Xa"), el("SET_PWM", duty="50", freq=1000, name="Pout")],
                               mcu="pic10f200", pins={**PINS, "Pout": "GP2"}))
    (problem,) = [d for d in found.value.diagnostics if d.code == "LD504"]
    assert problem.span is not None and problem.span.line == 0 and "the PIC10F200 has no PWM output" in problem.message


# --- the scan-time budget ---------------------------------------------------------------------------


@needs_gpsim
@pytest.mark.slow
def test_worst_case_is_sound_and_tight_on_a_loop_free_program(tmp_path):
    prog = program([contact("Xa"), timer("TON", "Ton", 50_000), coil("Ya")],
                   [contact("Xb"), el("OSR"), counter("CTU", "Cup", 1000)],
                   [el("GEQ", op1="Cup", op2="3"), contact("Xa"), el("ADD", dest="s", op1="s", op2="Cup")],
                   mcu="pic10f202", pins={"Xa": "GP3", "Xb": "GP0", "Ya": "GP1"}, sizes={"s": 2},
                   crystal_hz=4_000_000)
    inputs = [(0.0, "GP3", 1), *((max(0.0, (s - 0.5) * 10), "GP0", s % 2) for s in range(80))]
    build, measured = measure_pic(prog, inputs, 800, tmp_path)
    assert build.budget.loops == (), "not loop-free"
    assert _sound(build, measured) <= 1.25


@needs_gpsim
@pytest.mark.slow
def test_worst_case_covers_a_division(tmp_path):
    prog = program([contact("Xa"), par([el("DIV", dest="q", op1="s", op2="7")], [el("ADD", dest="s", op1="s", op2="13")])],
                   mcu="pic10f202", pins={"Xa": "GP3", "Ya": "GP1"}, sizes={"q": 2, "s": 2}, crystal_hz=4_000_000)
    build, measured = measure_pic(prog, [(0.0, "GP3", 1)], 500, tmp_path)
    _sound(build, measured)


# --- random programs ------------------------------------------------------------------------------------

# three rungs at most and 8- and 16-bit variables, so that more of the programs drawn fit 16 or 24 bytes
# of RAM: 300 passing programs with 1,742 left out instead of 3,336, in 0.42 of the CPU time
BOARDS = tuple(Board(part, "pic10", f"Microchip {part.upper()} 6-SOT", ("GP3", "GP0"), ("GP1", "GP2"), uart=False,
                     crystal_hz=4_000_000, cycle_us=10_000, left_out=PIC16_PERIPHERALS, rungs=3, widest=2)
               for part in PARTS)


def _follows(case, folder: Path) -> None:
    """A random program that fits the part (program memory, RAM, the stack)
    and whose scan fits its cycle, in gpsim beside the simulator: no mismatch."""
    from compiler.run.record import CycleOverrun

    try:
        problems = differential(case.program, case.events, case.scans, folder)
    except CompileError as problem:
        assume(not all(d.code in (FLASH_FULL, RAM_FULL) for d in problem.diagnostics))
        raise
    except CycleOverrun:
        assume(False)
    assert problems == [], "\n".join(problems)


@needs_gpsim
@settings(max_examples=3, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases(BOARDS))
def test_a_sample_of_random_programs_follows_the_simulator(case, tmp_path_factory):
    _follows(case, tmp_path_factory.mktemp("random"))


@needs_gpsim
@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True, database=None, suppress_health_check=list(HealthCheck))
@given(case=cases(BOARDS))
def test_random_programs_follow_the_simulator_on_pic10(case, tmp_path_factory):
    _follows(case, tmp_path_factory.mktemp("random"))


def test_the_part_is_read_through_the_pic16_part():
    part = Part.of(find_device("pic10f202"))
    assert part.reg("GPIO") == 6 and [list(r) for r in part.ram_ranges()] == [list(range(8, 32))]


def test_a_scan_longer_than_a_turn_of_timer0_is_warned():
    """10 ms at 4 MHz: Timer0 at 1:16, 625 ticks a cycle; a 5 ms DELAY fits the cycle but not a turn
    of the timer (4,096 cycles), between two of the wait's reads."""
    build = compiler.build(program([contact("Xa"), el("DELAY", delay="5000")], mcu="pic10f202", pins=PINS,
                                   crystal_hz=4_000_000))
    (warning,) = [w for w in build.warnings if w.code == "LD712"]
    assert "more than one turn of Timer0" in warning.message
    assert build.budget.limit == (256 * 16 - 20, "one turn of Timer0")


@needs_gpsim
def test_a_scenario_passes_on_the_pic10_image(capsys):
    """`ladder test --on pic10`: the timer and the counter of p10f200_basic, in gpsim."""
    from ladder.cli import main

    status = main(["test", "--on", "pic10", str(Path(__file__).resolve().parent / "pic10_programs" / "p10f200_basic.scn")])
    out = capsys.readouterr().out
    assert status == 0 and "1 passed, 0 failed" in out, out
