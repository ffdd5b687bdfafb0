"""Every AVR part LDmicro 5.4.1.1 lists: its pins against LDmicro's own MCU
table (mcutable.h in the LDmicro source in ../shared), every LDmicro name and
lower-case part name accepted and built, and the corpus programs moved to
each part simavr has a core for, run beside the simulator scan for scan
(slow). The register addresses, vectors and memory sizes are checked against
avr-libc in test_compiler_parts.py; random programs on these parts are in
test_compiler_random.py."""

from __future__ import annotations

import re
import subprocess
import sys
import tarfile
from dataclasses import replace
from functools import cache

import pytest
from builders import coil, contact, el, program
from corpus import SHARED
from test_compiler_corpus import CASES
from test_compiler_harness import Event, differential, load, needs_simavr, run_hex
from test_compiler_random import NEW_AVR_BOARDS, Board

import compiler
from compiler.errors import CompileError
from compiler.run import simavr
from lang.devices import find_device, is_known_ldmicro_name
from lang.families import compiled
from lang.ldfile import read_ld, write_ld
from lang.model import PinAssignment, Program, Span

LDMICRO_SOURCE = SHARED / "tools" / "ldmicro" / "ldmicro-5.4.1.1-src.tar.gz"
# LDmicro names the back end does not compile: none
NOT_BUILT: set[str] = set()
# the parts and packages added for issue 20, whose pin labels are LDmicro
# 5.4.1.1's; the first nine parts keep the labels of the LDmicro exports they
# were made from
NEW_PARTS = {"atmega48", "atmega88", "atmega168", "atmega164p", "atmega324p", "atmega644p", "atmega32u4",
             "at90usb647", "attiny85", "attiny10"}
NEW_PACKAGES = {"Atmel AVR ATmega1284 44-Pin packages"}

# LDmicro offers the reset pin PC6 as an I/O pin on the 32-pin packages; our
# data leaves it RESET, as LDmicro's own 28-pin tables do (the pin is an I/O
# only with the RSTDISBL fuse programmed, which ends serial programming)
RESET_AS_IO = {"Atmel AVR ATmega8 32-Pin packages": 29, "Atmel AVR ATmega328 32-Pin packages": 29}


@cache
def _mcutable() -> str:
    with tarfile.open(LDMICRO_SOURCE) as archive:
        member = archive.extractfile("ldmicro-5.4.1.1/ldmicro/mcutable.h")
        assert member is not None
        text = member.read().decode("latin-1")
    return re.sub(r"//[^\n]*", "", text)  # commented-out rows are not LDmicro's


def _arrays(kind: str) -> dict[str, str]:
    return {m.group(1): m.group(2) for m in re.finditer(rf"{kind}\s+(\w+)\[\]\s*=\s*\{{(.*?)\}};", _mcutable(), re.S)}


def _channel(mux: int) -> int:
    """LDmicro's A/D mux value as a channel: 8-15 are 0x08-0x0F on the
    ATmega2560, MUX5 (0x20) with 0-5 on the ATmega32U4."""
    return 8 + (mux & 7) if mux & 0x20 else mux


@cache
def ldmicro_avrs() -> dict[str, dict]:
    """LDmicro name -> its I/O pins {pin: (port bit, label)}, A/D inputs
    {pin: channel} and UART pins (rx, tx) (0, 0 without one)."""
    io_tables = {name: {int(m.group(3)): (f"P{m.group(1)}{m.group(2)}", m.group(4))
                        for m in re.finditer(r"\{\s*'([A-L])',\s*(\d+),\s*(\d+)\s*,\s*\"([^\"]*)\"", body)}
                 for name, body in _arrays("McuIoPinInfo").items()}
    adc_tables = {name: {int(pin): _channel(int(mux, 0))
                         for pin, mux in re.findall(r"\{\s*(\d+),\s*(0x[0-9A-Fa-f]+|\d+)\s*\}", body)}
                  for name, body in _arrays("McuAdcPinInfo").items()}
    table = _mcutable()[_mcutable().index("SupportedMcus_"):]
    parts = {}
    for m in re.finditer(r"\{\s*\"(Atmel AVR [^\"]+)\",(.*?)\{\{0,0\}\}", table, re.S):
        words = re.findall(r"\w+", m.group(2))
        io = next(w for w in words if w in io_tables)
        adc = next((w for w in words if w in adc_tables), None)
        uart = re.search(r"\{\s*(\d+)\s*,\s*(\d+)\s*\}", m.group(2).split(io, 1)[1])
        parts[m.group(1)] = {"io": io_tables[io], "adc": adc_tables.get(adc, {}),
                             "uart": (int(uart.group(1)), int(uart.group(2)))}
    return parts


def test_every_ldmicro_avr_name_is_found_and_built():
    assert len(ldmicro_avrs()) == 24
    for name in ldmicro_avrs():
        device = find_device(name)
        if name in NOT_BUILT:
            assert device is None and is_known_ldmicro_name(name), name
            continue
        assert device is not None and device.ldmicro_name == name and compiled(device), name


@pytest.mark.parametrize("name", sorted(set(ldmicro_avrs()) - NOT_BUILT))
def test_pins_are_ldmicros(name):
    """The package's port bits on LDmicro's pin numbers, nothing more; the A/D
    inputs on its pins with its channels; the UART on its pins."""
    device, table = find_device(name), ldmicro_avrs()[name]
    io = {n: bit for n, (bit, _) in table["io"].items()}
    if name in RESET_AS_IO:
        assert io.pop(RESET_AS_IO[name]) == "PC6" and device.pin(RESET_AS_IO[name]).name == "RESET"
    assert {pin.number: pin.name for pin in device.io_pins()} == io
    if device.part in NEW_PARTS or name in NEW_PACKAGES:
        assert {pin.number: pin.label for pin in device.io_pins()} == {n: label for n, (_, label) in table["io"].items()}
    adc = {device.pin(name).number: channel for name, channel in device.adc.items() if device.pin(name)}
    assert adc == table["adc"]
    uart = tuple(device.pin(device.uart[end]).number for end in ("rx", "tx")) if device.uart else (0, 0)
    assert uart == table["uart"]


# LDmicro's lower-case part names, as `--target` takes them
TARGETS = {"atmega48": "atmega48", "atmega88": "atmega88", "atmega168": "atmega168", "atmega164": "atmega164p",
           "atmega324": "atmega324p", "atmega644": "atmega644p", "atmega1284": "atmega1284p",
           "atmega32u4": "atmega32u4", "at90usb647": "at90usb647", "attiny85": "attiny85",
           "attiny10": "attiny10"}


@pytest.mark.parametrize("name", sorted(TARGETS))
def test_lower_case_part_names_are_targets(name):
    assert compiler.target_device(load("sample/traffic.ld"), name).part == TARGETS[name]


def moved(prog: Program, board: Board) -> Program:
    """The program for the board's part: each pin by its port bit where the
    part has it (and it is neither the UART's nor, for a program reading
    one, the board's A/D input), else on the part's next free port bit; the
    A/D input on the board's."""
    device = find_device(board.ldmicro)
    source = find_device(prog.settings.mcu)
    reserved = {*device.uart.values(), *(board.adc for name in prog.pins if name[0] == "A")}
    free = [pin.name for pin in device.io_pins() if pin.name not in reserved]
    wanted = {name: source.pin(a.pin).name for name, a in prog.pins.items()}
    taken = {bit for name, bit in wanted.items() if name[0] != "A" and bit in free}
    spare = iter(bit for bit in free if bit not in taken)
    for name in prog.pins:
        if name[0] == "A":
            pin = board.adc
        elif wanted[name] in free:
            pin = wanted[name]
        else:
            pin = next(spare)
        prog.pins[name] = PinAssignment(name, pin)
    return replace(prog, settings=replace(prog.settings, mcu=board.ldmicro))


# six port bits and no UART: not the 16 outputs of ctu_ctd_ctc_ctr, nor hello's UART
FITS_ATTINY85 = ("sample/traffic.ld", "reg/tests/timers-counters.ld", "sample/ctu_ctd_ctc.ld", "Tests/test-adc.ld")
CORPUS = ("sample/traffic.ld", "reg/tests/timers-counters.ld", "sample/ctu_ctd_ctc.ld", "sample/ctu_ctd_ctc_ctr.ld",
          "sample/hello.ld", "Tests/test-adc.ld")


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("board, path", [(board, path) for board in NEW_AVR_BOARDS for path in CORPUS
                                          if board.part != "attiny85" or path in FITS_ATTINY85],
                         ids=lambda x: getattr(x, "ldmicro", x))
def test_corpus_programs_moved_to_the_part_follow_the_simulator(path, board, tmp_path):
    events, scans = CASES[path]
    assert differential(moved(load(path), board), events, scans, tmp_path) == []


# --- the ATtiny85 ------------------------------------------------------------------------------

TINY = "Atmel AVR ATtiny85 8-Pin packages"


def test_attiny85_uart_is_a_located_error_naming_the_part():
    send = el("UART_SEND", var="v", wait=0)
    with pytest.raises(CompileError) as refused:
        compiler.build(program([contact("Xa"), send], mcu=TINY, pins={"Xa": "PB3"}))
    [found] = refused.value.diagnostics
    assert (found.code, found.span) == ("LD503", Span(0, 100, 0, 150))
    assert "the ATtiny85 has no UART" in found.message


def test_attiny85_pwm_on_timer0_is_refused_as_the_cycles():
    pwm = el("SET_PWM", duty="50", freq=1000, name="P")
    with pytest.raises(CompileError) as refused:
        compiler.build(program([contact("Xa"), pwm], mcu=TINY, pins={"Xa": "PB3", "P": "PB0"}))
    assert [(d.code, d.message) for d in refused.value.diagnostics] == [
        ("LD708", "PWM on OC0A: Timer0 makes the scan cycle; use an 8-bit timer's output")]


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("crystal_hz, cycle_us, delay_us", [(8_000_000, 10_000, 0), (16_000_000, 10_000, 1500),
                                                             (1_000_000, 10_000, 0), (8_000_000, 1_000, 0)])
def test_attiny85_scans_start_one_cycle_apart(crystal_hz, cycle_us, delay_us, tmp_path):
    """Timer0 runs free and its overflows are counted in software: scan k
    starts k cycles after the first, which starts at once, a scan of 1.5 ms
    (under one turn of the timer: 4 ms for 10 ms at 16 MHz) included."""
    rungs = [[contact("Xa"), coil("Ya")]] + ([[el("DELAY", delay=str(delay_us))]] if delay_us else [])
    prog = program(*rungs, mcu=TINY, pins={"Xa": "PB3", "Ya": "PB0", "YPlcCycleDuty": "PB2"},
                   cycle_us=cycle_us, crystal_hz=crystal_hz, cycle_duty=True)
    build = compiler.build(prog)
    build.write(tmp_path / "p.hex")
    cycles = crystal_hz * cycle_us // 10**6
    run = simavr.run_avr(tmp_path / "p.hex", "attiny85", crystal_hz, ["watch B 2", f"run {40 * cycles}"])
    starts = [cycle for cycle, pin, level in run.edges if pin == "B2" and level]
    assert len(starts) >= 39
    assert starts[0] < crystal_hz // 10_000  # the first scan at once (start-up under 0.1 ms)
    # on the grid of the first, late by at most a pass or two of the wait loop (about 20 cycles each): no drift
    assert all(0 <= start - starts[0] - k * cycles <= 40 for k, start in enumerate(starts)), starts


@needs_simavr
@pytest.mark.slow
def test_attiny85_pwm_programs_timer1(tmp_path):
    """simavr does not run the ATtiny85's Timer1: its registers after SET PWM
    are read for the datasheet's values: TCCR1 = PWM1A | COM1A1 | CS1 = 7
    (clock / 64: 976.6 Hz, the nearest 1 kHz at 16 MHz), OCR1A = 50 % of 256
    as every AVR part scales it (duty * 655 / 256 = 127), OCR1C = 255 (the
    period); and the pin an output."""
    prog = program([contact("Xa"), el("SET_PWM", duty="50", freq=1000, name="P")], mcu=TINY,
                   pins={"Xa": "PB3", "P": "PB1"}, crystal_hz=16_000_000)
    compiler.build(prog).write(tmp_path / "p.hex")
    run = simavr.run_avr(tmp_path / "p.hex", "attiny85", 16_000_000,
                         ["drive B 3 1", "run 400000", "peek 77 4", "read B"])
    [peeked] = [line.split()[2:] for line in run.raw.splitlines() if line.startswith("@peek")]
    ocr1c, ocr1a, _, tccr1 = (int(byte, 16) for byte in peeked)  # data addresses 0x4D..0x50
    assert (tccr1, ocr1a, ocr1c) == (0x40 | 0x20 | 7, 127, 255)
    assert run.port("B")[1] & 1 << 1  # DDRB1


@needs_simavr
@pytest.mark.slow
def test_attiny85_multiplies_without_mul(tmp_path):
    """The ATtiny85 has no MUL: products of 1, 2 and 4 bytes (signed, with
    overflowing ones) and BCD2BIN by shifts and adds, against the simulator
    while the operands step through their range."""
    prog = program([contact("Xa"), el("ADD", dest="a", op1="a", op2="-37")],
                   [contact("Xa"), el("ADD", dest="b", op1="b", op2="1013")],
                   [el("MUL", dest="p1", op1="a", op2="b")], [el("MUL", dest="p2", op1="a", op2="b")],
                   [el("MUL", dest="p4", op1="a", op2="b")], [el("MUL", dest="q4", op1="b", op2="-70001")],
                   [el("MOVE", dest="d", src="151521030")], [el("BCD2BIN", dest="n", src="d")],  # digits 9, 8, 7, 6
                   mcu=TINY, pins={"Xa": "PB3"}, sizes={"a": 2, "b": 4, "p1": 1, "p2": 2, "p4": 4, "q4": 4, "d": 4,
                                                        "n": 4})
    events = [Event(0, "Xa", 1)]
    assert differential(prog, events, 200, tmp_path) == []


def _delayed(delay_us: int):
    return program([contact("Xa"), coil("Ya")], [el("DELAY", delay=str(delay_us))], mcu=TINY,
                   pins={"Xa": "PB3", "Ya": "PB0", "YPlcCycleDuty": "PB2"}, crystal_hz=8_000_000, cycle_duty=True)


def test_attiny85_a_scan_longer_than_a_turn_of_timer0_is_warned():
    """10 ms at 8 MHz: Timer0 at clock / 64 turns in 2,048 µs."""
    assert compiler.build(_delayed(1900)).warnings == []
    [warning] = compiler.build(_delayed(3000)).warnings
    assert warning.code == "LD712"
    assert "more than one turn of Timer0 (2,048 µs, 16,384 cycles): the cycle timer would lose time" in warning.message


@needs_simavr
@pytest.mark.slow
def test_attiny85_a_scan_longer_than_a_turn_of_timer0_stretches_the_cycle(tmp_path):
    """What LD712 warns of: with a 3 ms scan some cycles are a turn long."""
    compiler.build(_delayed(3000)).write(tmp_path / "p.hex")
    run = simavr.run_avr(tmp_path / "p.hex", "attiny85", 8_000_000, ["watch B 2", "run 1600000"])
    starts = [cycle for cycle, pin, level in run.edges if pin == "B2" and level]
    assert max(b - a for a, b in zip(starts, starts[1:])) > 80_000 + 16_000


@pytest.mark.parametrize("name", sorted(set(ldmicro_avrs()) - NOT_BUILT))
def test_an_ld_file_naming_the_part_builds(name):
    """A `MICRO=` line of every LDmicro AVR name, the pins by package number
    as LDmicro writes them, read back and built for that package."""
    device = find_device(name)
    first, second = [pin.name for pin in device.io_pins() if pin.name not in device.uart.values()][:2]
    prog, problems = read_ld(write_ld(program([contact("Xa"), coil("Ya")], mcu=name, pins={"Xa": first, "Ya": second})))
    assert not problems
    assert f"MICRO={name}" in write_ld(prog)
    build = compiler.build(prog)
    assert (build.device.part, build.device.package) == (device.part, device.package)


def test_ladder_parts_builds_every_ldmicro_avr():
    listed = subprocess.run([sys.executable, "-m", "ladder", "parts"], capture_output=True, text=True, timeout=120,
                            check=True).stdout
    rows = {line.split(None, 4)[4]: line.split()[3] for line in listed.splitlines()[1:] if "Atmel AVR" in line}
    assert rows == {name: "yes" for name in set(ldmicro_avrs()) - NOT_BUILT}


@needs_simavr
@pytest.mark.slow
def test_atmega32u4_echoes_on_its_usart1(tmp_path):
    """The ATmega32U4 has only USART1: the bytes fed to it (the harness's
    `uart 1`) are received, as the simulator receives them, and sent back."""
    prog = program([el("UART_RECV", var="got", bytes=1, wait=0), el("UART_SEND", var="got", wait=0)],
                   mcu="Atmel AVR ATmega32U4 44-Pin packages", crystal_hz=16_000_000, cycle_us=4000)
    events = [Event(5, "uart", 65), Event(12, "uart", 200), Event(20, "uart", 7)]
    assert differential(prog, events, 30, tmp_path) == []
    build = compiler.build(prog)
    build.write(tmp_path / "echo.hex")
    assert run_hex(build, tmp_path / "echo.hex", events, 30, []).run.uart_bytes() == bytes([65, 200, 7])
