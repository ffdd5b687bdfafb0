"""`ladder build --emit arduino --board uno|nano|mega`: the sketch folder, its
pins, and (marker `arduino`, their own step of .ci/run) the sketches of the
conveyor example and of examples/traffic-uno.ladder built offline by
arduino-builder against Debian's Arduino AVR core and run in simavr, their
output pins following the simulator scan for scan; boards.json checked
against the core's own pin tables."""

from __future__ import annotations

import dataclasses
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from test_compiler_harness import Event, simulate

from compiler.c.arduino import BOARDS
from compiler.run.record import record_pins
from ladder.cli import main
from lang.devices import find_device
from lang.instructions import INSTRUCTIONS
from lang.loader import load_path
from lang.model import Element, PinAssignment, Program, Rung, Series, Settings
from lang.textform.writer import render_program

ROOT = Path(__file__).resolve().parents[1]
CORE = Path("/usr/share/arduino/hardware")
# Debian's arduino-core-avr 1.8.7 uses C++17's DECIMAL_DIG, which its avr-gcc 5.4 lacks in gnu++11
BUILDER_PREFS = "compiler.cpp.extra_flags=-DDECIMAL_DIG=17"


def run(capsys, *argv) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def _sketch(capsys, program: Path, folder: Path, board: str) -> Path:
    source = folder / program.name
    if source != program:
        shutil.copyfile(program, source)
    status, out, err = run(capsys, "build", str(source), "--emit", "arduino", "--board", board)
    assert status == 0, out + err
    return folder / program.stem


def test_the_sketch_folder_has_the_ino_and_the_c(capsys, tmp_path):
    sketch = _sketch(capsys, ROOT / "examples" / "traffic-uno.ladder", tmp_path, "uno")
    assert sorted(p.name for p in sketch.iterdir()) == ["ladder.h", "traffic-uno.c", "traffic-uno.h",
                                                        "traffic-uno.ino"]
    ino = (sketch / "traffic-uno.ino").read_text()
    assert "static const uint8_t PIN_Yred = 8; // D8 (PB0)" in ino
    assert "pinMode(PIN_Xbutton1, INPUT_PULLUP);" in ino  # LDmicro's pull-ups: on unless the list clears them
    assert "next += 10000UL;" in ino and "PlcCycle();" in ino


@pytest.mark.parametrize("given, folder", [("ard/blink", "ard/blink"), ("ard/blink/blink.ino", "ard/blink"),
                                           ("ard/blink.ino", None)])
def test_o_names_the_sketch_folder_or_its_ino(capsys, tmp_path, given, folder):
    """-o DIR, or DIR/DIR.ino for the sketch file in it; an .ino in a folder
    of another name the Arduino IDE would not open, so it is refused, saying what would do."""
    shutil.copyfile(ROOT / "examples" / "traffic-uno.ladder", tmp_path / "t.ladder")
    status, _, err = run(capsys, "build", str(tmp_path / "t.ladder"), "--emit", "arduino", "--board", "uno",
                         "-o", str(tmp_path / given))
    if folder is None:
        assert status == 2 and f"-o {tmp_path / 'ard' / 'blink'}" in err, err
        assert not (tmp_path / "ard").exists()
    else:
        assert status == 0, err
        assert (tmp_path / folder / "blink.ino").is_file() and (tmp_path / folder / "blink.c").is_file()


def test_pins_may_be_arduino_names_port_bits_or_package_pins(capsys, tmp_path):
    program = ROOT / "examples" / "conveyor.ladder"  # package pins 4, 5, 18, 19 of the ATmega328P
    for board in ("uno", "nano"):  # the board's own chip: its package pins
        (tmp_path / board).mkdir()
        ino = (_sketch(capsys, program, tmp_path / board, board) / "conveyor.ino").read_text()
        assert "PIN_Xstart = 2; // D2 (PD2)" in ino and "PIN_Ymotor = 13; // D13 (PB5)" in ino
    # with no part selected, pins may be the board's own names, or port bits of the board's chip
    loaded, _ = load_path(program)
    loaded = dataclasses.replace(loaded, settings=dataclasses.replace(loaded.settings, mcu=""))
    for name, pin in {"Xstart": "D7", "Xstop": "A1", "Yhorn": "D12", "Ymotor": "PB7"}.items():
        loaded.pins[name] = PinAssignment(name, pin)
    (tmp_path / "named").mkdir()
    (tmp_path / "named" / "conveyor.ladder").write_text(render_program(loaded))
    ino = (_sketch(capsys, tmp_path / "named" / "conveyor.ladder", tmp_path / "named", "mega") /
           "conveyor.ino").read_text()
    assert "PIN_Xstart = 7; // D7 (PH4)" in ino and "PIN_Xstop = 55; // A1 (PF1)" in ino
    assert "PIN_Ymotor = 13; // D13 (PB7)" in ino
    assert capsys.readouterr().err == ""


def _for_the_mega(capsys, tmp_path, text: str, *options) -> tuple[int, str, str]:
    source = tmp_path / "prog.ladder"
    source.write_text(text)
    return run(capsys, "build", str(source), "--emit", "arduino", "--board", "mega", *options)


def test_package_pins_of_another_chip_are_refused_naming_the_boards_that_fit(capsys, tmp_path):
    text = (ROOT / "examples" / "conveyor.ladder").read_text()
    for options in ((), ("--keep-port-bits",)):
        status, out, _ = _for_the_mega(capsys, tmp_path, text, *options)
        assert status == 1 and not (tmp_path / "prog").exists()
        assert re.search(r"prog\.ladder:\d+:3: error LD715 'Xstart' is at pin 4 of the ATmega328P \(28-PDIP\), a "
                         r"package pin number, which means nothing on the Arduino Mega 2560's ATmega2560: build "
                         r"with --board uno or nano, or give it by port bit \(PD2\) and build with --keep-port-bits",
                         out)
        assert out.count("error LD715") == 4


def test_port_bits_of_another_chip_are_refused_unless_kept_each_move_shown(capsys, tmp_path):
    text = (ROOT / "examples" / "traffic-uno.ladder").read_text()
    status, out, _ = _for_the_mega(capsys, tmp_path, text)
    assert status == 1 and not (tmp_path / "prog").exists()
    assert "error LD715 'Xbutton1' is at PD2, a port bit of the ATmega328P: D19 on the Arduino Mega 2560, D2 on " \
           "the Arduino Uno; build with --board uno or nano, or add --keep-port-bits to use D19" in out
    assert out.count("error LD715") == 6
    status, out, err = _for_the_mega(capsys, tmp_path, text, "--keep-port-bits")
    assert status == 0
    assert "warning LD715 'Xbutton1': PD2 → D19 on the Arduino Mega 2560 (was D2 on the Arduino Uno)" in err
    assert "warning LD715 'Ywait': PB5 → D11 on the Arduino Mega 2560 (was D13 on the Arduino Uno)" in err
    assert "PIN_Xbutton1 = 19; // D19 (PD2)" in (tmp_path / "prog" / "prog.ino").read_text()


def test_a_chip_no_board_carries_has_no_board_to_suggest(capsys, tmp_path):
    text = (ROOT / "examples" / "traffic-uno.ladder").read_text().replace(
        "for 'Atmel AVR ATmega328 28-PDIP'", "for 'Atmel AVR ATmega16 40-PDIP'")
    status, out, _ = _for_the_mega(capsys, tmp_path, text)
    assert status == 1
    assert "error LD715 'Xbutton1' is at PD2, a port bit of the ATmega16: D19 on the Arduino Mega 2560; add " \
           "--keep-port-bits to use D19" in out
    status, _, err = _for_the_mega(capsys, tmp_path, text, "--keep-port-bits")
    assert status == 0 and "'Xbutton1': PD2 → D19 on the Arduino Mega 2560\n" in err


def test_a_port_bit_the_board_lacks_names_the_board_that_has_it(capsys, tmp_path):
    text = (ROOT / "examples" / "traffic-uno.ladder").read_text().replace("| PB0 | PB0   |", "| PD4 | PD4   |")
    status, out, _ = _for_the_mega(capsys, tmp_path, text, "--keep-port-bits")
    assert status == 1  # the Mega's ATmega2560 has PD4, but no header pin of the board
    assert "error LD715 'Yred' is at PD4, a port bit of the ATmega328P, which the Arduino Mega 2560 does not " \
           "bring out: build with --board uno or nano" in out
    mega = text.replace("for 'Atmel AVR ATmega328 28-PDIP'", "for 'Atmel AVR ATmega2560 100-TQFP'").replace(
        "| PD4 | PD4   |", "| PE4 | PE4   |")
    source = tmp_path / "mega.ladder"
    source.write_text(mega)
    status, out, _ = run(capsys, "build", str(source), "--emit", "arduino", "--board", "uno", "--keep-port-bits")
    assert status == 1
    assert "error LD715 'Yred' is at PE4, a port bit of the ATmega2560, which the Arduino Uno's ATmega328P does " \
           "not have: build with --board mega" in out


def test_keep_port_bits_goes_with_a_board(capsys, tmp_path):
    status, _, err = run(capsys, "build", str(ROOT / "examples" / "conveyor.ladder"), "--keep-port-bits")
    assert status == 2 and "--keep-port-bits goes with --board" in err


def test_a_pin_the_board_lacks_is_a_located_error(capsys, tmp_path):
    text = (ROOT / "examples" / "traffic-uno.ladder").read_text().replace("| PB5 | PB5   |", "| PB6 | PB6   |")
    source = tmp_path / "t.ladder"
    source.write_text(text)
    status, out, _ = run(capsys, "build", str(source), "--emit", "arduino", "--board", "uno")
    assert status == 1
    assert re.search(r"t\.ladder:\d+:\d+: error LD702 'Ywait' is on pin PB6, which is not one of the Arduino Uno's", out)
    assert not (tmp_path / "t").exists()
    assert run(capsys, "build", str(source), "--emit", "arduino")[0] == 2  # no --board


@pytest.mark.arduino
@pytest.mark.parametrize("board", sorted(BOARDS))
def test_boards_match_the_arduino_cores_pin_tables(board):
    variant = {"uno": "standard", "nano": "standard", "mega": "mega"}[board]
    text = (CORE / "arduino" / "avr" / "variants" / variant / "pins_arduino.h").read_text()

    def table(name: str) -> list[str]:
        body = text[text.index(name):]
        body = re.sub(r"/\*.*?\*/|//[^\n]*", "", body[body.index("{") + 1:body.index("};")], flags=re.S)
        return [x.strip() for x in body.split(",") if x.strip()]

    ports, masks = table("digital_pin_to_port_PGM[]"), table("digital_pin_to_bit_mask_PGM[]")
    bits = [re.search(r"\d+", mask).group() for mask in masks]
    assert list(BOARDS[board].pins) == [f"P{port[1]}{bit}" for port, bit in zip(ports, bits)]
    assert f"#define PIN_A0   ({BOARDS[board].analog_first})" in text


def _build(sketch: Path, board: str) -> Path:
    build = sketch.parent / f"build-{board}"
    build.mkdir()
    done = subprocess.run(["arduino-builder", "-hardware", str(CORE), "-hardware", "/usr/share/arduino-builder",
                           "-tools", "/usr/bin", "-fqbn", BOARDS[board].fqbn, f"-prefs={BUILDER_PREFS}",
                           "-build-path", str(build), str(sketch / f"{sketch.name}.ino")],
                          capture_output=True, text=True, timeout=200)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return build / f"{sketch.name}.ino.hex"


CASES = {
    "conveyor": (ROOT / "examples" / "conveyor.ladder", 300,
                 [Event(0, "Xstart", 0), Event(0, "Xstop", 0), Event(10, "Xstart", 1), Event(20, "Xstart", 0),
                  Event(250, "Xstop", 1), Event(260, "Xstop", 0), Event(270, "Xstart", 1)]),
    "traffic-uno": (ROOT / "examples" / "traffic-uno.ladder", 1200,
                    [Event(0, "Xbutton1", 1), Event(0, "Xbutton2", 1), Event(120, "Xbutton1", 0),
                     Event(125, "Xbutton1", 1)]),
}


@pytest.mark.arduino
@pytest.mark.parametrize("name", sorted(CASES))
def test_the_sketch_builds_offline_and_runs_in_simavr_following_the_simulator(name, capsys, tmp_path):
    path, scans, events = CASES[name]
    hex_path = _build(_sketch(capsys, path, tmp_path, "uno"), "uno")
    program, _ = load_path(path)
    device = find_device(program.settings.mcu)
    pins = {name: device.pin(assignment.pin).name for name, assignment in program.pins.items()}
    recording = record_pins(hex_path, "atmega328p", 16_000_000, program.settings.cycle_us, events, scans, pins)
    expected = simulate(program, events, scans, recording.names)
    differences = [f"scan {scan}: {n} simulator {want[n]}, sketch {got[n]}"
                   for scan, (want, got) in enumerate(zip(expected, recording.rows)) for n in recording.names
                   if want[n] != got[n]]
    assert any(row[n] for row in expected for n in recording.names)  # the outputs do something
    assert not differences, "\n".join(differences[:20])


def _element(kind: str, **args) -> Element:
    full = {f.name: f.default for f in INSTRUCTIONS[kind].fields}
    full.update(args)
    return Element(kind, full)


@pytest.mark.arduino
@pytest.mark.parametrize("board", sorted(BOARDS))
def test_a_sketch_with_every_peripheral_builds_for_every_board(board, capsys, tmp_path):
    # A/D on A0, PWM on D9 (0-1024), the UART, PERSIST, a DELAY: every runtime function the sketch writes
    rungs = [Rung(Series([_element("READ_ADC", name="Apot", refs=0)])),
             Rung(Series([_element("SET_PWM", name="Pled", duty="Apot", freq=1000, resolution="0-1024")])),
             Rung(Series([_element("CONTACTS", name="Xsend", negated=0), _element("OSR"),
                          _element("UART_SEND", var="Apot", bytes=1, wait=0)])),
             Rung(Series([_element("UART_RECV_AVAIL"), _element("UART_RECV", var="got", bytes=1, wait=0)])),
             Rung(Series([_element("CONTACTS", name="Xsend", negated=0), _element("DELAY", delay="20")])),
             Rung(Series([_element("PERSIST", var="got")]))]
    program = Program(Settings(mcu="", cycle_us=10_000, crystal_hz=16_000_000, baud=9600), rungs)
    for name, pin in {"Apot": "A0", "Pled": "D9", "Xsend": "D2"}.items():
        program.pins[name] = PinAssignment(name, pin)
    source = tmp_path / "io.ladder"
    source.write_text(render_program(program))
    status, out, err = run(capsys, "build", str(source), "--emit", "arduino", "--board", board)
    assert status == 0, out + err
    ino = (tmp_path / "io" / "io.ino").read_text()
    assert "analogRead(PIN_Apot)" in ino and "Serial.begin(9600);" in ino and "EEPROM.write" in ino
    assert _build(tmp_path / "io", board).exists()
