"""LDmicro .ld files: the whole corpus, legacy forms, LDmicro 5.4's own output,
located diagnostics for bad input (ldmicro-formats.md §2, §3)."""

from __future__ import annotations

import random
import re
import time
import warnings
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lang.codes import BAD_VALUE, LD_SYNTAX, UNREADABLE
from lang.diagnostics import ERROR, WARNING
from lang.instructions import INSTRUCTIONS, LD_KEYWORDS
from lang.ldfile import (
    element_line,
    read_ld,
    read_ld_bytes,
    write_ld,
    write_ld_bytes,
)
from lang.model import Element, Parallel, PinAssignment, Program, Rung, Series, Settings

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus"
CORPUS_FILES = sorted((CORPUS / "ldmicro").rglob("*.ld")) + sorted((CORPUS / "ldmicro-export").glob("*.ld"))
SAMPLE = CORPUS / "ldmicro" / "sample"
EXPORT = CORPUS / "ldmicro-export"

# Files whose PROGRAM section is in the 0.2 form LDmicro 5.4 writes: "RUNG <n>",
# two blanks per level, every element in its long form. Not in this list: the
# other 0.2 files test-uart.ld (UART_RECV/UART_SEND short forms and a numeric
# FORMATTED_STRING, written by an older 5.x), sample/swatch2.ld (3-flag coils,
# blanks before a comment's line break), catalog.ld (hand-written, unnumbered
# rungs, 4-blank indentation) and test-i2c-2.ld, whose comment has a blank
# before a line break that we drop (docs/format.md: blanks ending a comment
# line carry nothing).
WRITTEN_BY_54 = [
    "ldmicro/Tests/test-adc.ld",
    "ldmicro/Tests/test-i2c-1.ld",
    "ldmicro/Tests/test-i2c-lcd16x2.ld",
    "ldmicro/Tests/test-pwm.ld",
    "ldmicro/Tests/test-spi.ld",
    "ldmicro-export/demo.ld",
    "ldmicro-export/longnames.ld",
]


def rel(path: Path) -> str:
    return path.relative_to(CORPUS).as_posix()


def load(path: Path) -> Program:
    program, diagnostics = read_ld_bytes(path.read_bytes())
    assert not [d for d in diagnostics if d.severity == ERROR], [d.format(rel(path)) for d in diagnostics]
    return program


def ld(body: str, version: str = "0.2", header: str = "") -> str:
    """A small .ld text with one PROGRAM section."""
    return f"LDmicro{version}\n{header}PROGRAM\n{body}"


def one(line: str, version: str = "0.2") -> Element:
    """The single element of a one-line rung; no error allowed."""
    program, diagnostics = read_ld(ld(f"RUNG 1\n  {line}\nEND\n", version))
    assert not [d for d in diagnostics if d.severity == ERROR], [d.format("t") for d in diagnostics]
    (rung,) = program.rungs
    (element,) = rung.circuit.items
    return element


def errors(text: str) -> list:
    program, diagnostics = read_ld(text)
    return [d for d in diagnostics if d.severity == ERROR]


def program_section(text: str) -> list[str]:
    text = text.replace("\r\n", "\n")
    return text[text.index("\nPROGRAM\n") + 1:].splitlines()


# --- the corpus ---------------------------------------------------------------------------


def test_corpus_is_there():
    assert len(CORPUS_FILES) == 66


@pytest.mark.parametrize("path", CORPUS_FILES, ids=rel)
def test_corpus_file_loads_without_diagnostics(path):
    program, diagnostics = read_ld_bytes(path.read_bytes())
    assert diagnostics == [], [d.format(rel(path)) for d in diagnostics]
    rung_lines = [line for line in path.read_bytes().decode("cp1252").splitlines()
                  if line.strip().startswith("RUNG")]
    assert len(program.rungs) == len(rung_lines)


def test_whole_corpus_loads_fast():
    data = [path.read_bytes() for path in CORPUS_FILES]
    read_ld_bytes(data[0])  # the parser is built once, on first use
    start = time.perf_counter()
    for item in data:
        read_ld_bytes(item)
    elapsed = time.perf_counter() - start
    assert elapsed < 1.0, f"the corpus took {elapsed:.2f} s to load"


@pytest.mark.parametrize("path", CORPUS_FILES, ids=rel)
def test_every_element_and_rung_points_at_its_line(path):
    program = load(path)
    lines = path.read_bytes().decode("cp1252").splitlines()
    for rung in program.rungs:
        assert rung.span is not None
        assert lines[rung.span.line].strip().startswith("RUNG")
        for element in rung.elements():
            span = element.span
            assert span is not None and span.line == span.end_line
            keyword = lines[span.line][span.col:].split()[0]
            assert LD_KEYWORDS[keyword].key == element.kind
            for name, arg_span in element.arg_spans.items():
                assert arg_span.line == span.line and arg_span.col >= span.col, name


def test_traffic():
    program = load(SAMPLE / "traffic.ld")
    s = program.settings
    assert s.ld_version == "0.1"
    assert s.mcu == "Atmel AVR ATmega128 64-TQFP"
    assert (s.cycle_us, s.cycle_timer, s.cycle_duty, s.crystal_hz) == (10000, 1, False, 4000000)
    assert s.compiled == "C:\\depot\\ldmicro\\out.hex"
    assert (s.baud, s.spi_rate, s.i2c_rate) == (9600, 1000000, 100000)  # no BAUD line: defaults
    assert program.pins == {
        "Xbutton1": PinAssignment("Xbutton1", 46), "Xbutton2": PinAssignment("Xbutton2", 45),
        "Ygreen": PinAssignment("Ygreen", 49), "Yred": PinAssignment("Yred", 51),
        "Ywait": PinAssignment("Ywait", 48), "Yyellow": PinAssignment("Yyellow", 50),
    }
    assert len(program.rungs) == 7
    first = program.rungs[0].circuit.items
    assert first == [
        Element("CONTACTS", {"name": "Rclock", "negated": 1, "set1": 0}),
        Element("TOF", {"name": "Ton", "delay": 500000, "adjust": -1}),
        Element("TON", {"name": "Toff", "delay": 500000, "adjust": -1}),
        Element("COIL", {"name": "Rclock", "type": " "}),
    ]
    assert program.rungs[1].circuit.items[1] == Element(
        "CTC", {"name": "Ccycle", "max": "19", "init": "0", "kind": "/"})
    fifth = program.rungs[4].circuit.items
    assert [e.kind for e in fifth[:2]] == ["GEQ", "LES"]
    assert fifth[2] == Parallel([Element("COIL", {"name": "Ygreen", "type": " "}),
                                 Element("COIL", {"name": "Rwait", "type": "R"})])
    sixth = program.rungs[5].circuit.items
    assert isinstance(sixth[0], Parallel) and isinstance(sixth[1], Parallel)
    assert isinstance(sixth[1].branches[0], Series)
    assert sixth[1].branches[0].items[2] == Element("MOVE", {"dest": "cycle", "src": "6"})
    assert sixth[1].branches[1] == Element("COIL", {"name": "Rwait", "type": "S"})
    # spans: the first rung is line 17 of the file, its TOF the line after the contact
    assert program.rungs[0].span.line == 16
    assert (first[1].span.line, first[1].span.col) == (18, 4)


def test_catalog_has_one_rung_per_element_type():
    program = load(EXPORT / "catalog.ld")
    text = (EXPORT / "catalog.ld").read_text()
    assert len(program.rungs) == text.count("\nRUNG\n") == 113
    kinds = [rung.circuit.items[0].kind for rung in program.rungs]
    assert all(len(rung.circuit.items) == 1 for rung in program.rungs)
    assert set(INSTRUCTIONS) <= set(kinds)  # every instruction of the table appears
    by_line = {}
    for rung in program.rungs:
        element = rung.circuit.items[0]
        by_line[text.splitlines()[element.span.line].strip()] = element
    expected = {
        "CONTACTS Xnew 0 1": ("CONTACTS", {"name": "Xnew", "negated": 0, "set1": 1}),
        "COIL Ynew 0 0 1 0": ("COIL", {"name": "Ynew", "type": "R"}),
        "COIL Ynew 0 0 0 1": ("COIL", {"name": "Ynew", "type": "T"}),
        "TON Tnew delayVar 0": ("TON", {"name": "Tnew", "delay": "delayVar", "adjust": 0}),
        "RTL Tnew 100000 0": ("RTL", {"name": "Tnew", "delay": 100000, "adjust": 0}),
        "TIME2DELAY delay 10": ("TIME2DELAY", {"name": "delay", "delay": 10}),
        "DELAY 10": ("DELAY", {"delay": "10"}),
        "CTD Cnew -10 0 /": ("CTD", {"name": "Cnew", "max": "-10", "init": "0", "kind": "/"}),
        "CTU Cnew 10 0 \\": ("CTU", {"name": "Cnew", "max": "10", "init": "0", "kind": "\\"}),
        "ADD dest src 1": ("ADD", {"dest": "dest", "op1": "src", "op2": "1"}),
        "NEG dest src": ("NEG", {"dest": "dest", "op1": "src"}),
        "SHIFT_REGISTER reg 7": ("SHIFT_REGISTER", {"name": "reg", "stages": 7}),
        "LOOK_UP_TABLE dest index 4 0 10 20 30 40 tabName": (
            "LOOK_UP_TABLE", {"dest": "dest", "index": "index", "values": ("10", "20", "30", "40"),
                              "as_string": 0, "table": "tabName"}),
        "PIECEWISE_LINEAR yvar xvar 2 0 0 10 100 name": (
            "PIECEWISE_LINEAR", {"dest": "yvar", "index": "xvar",
                                 "points": (("0", "0"), ("10", "100")), "table": "name"}),
        "READ_ADC ADCnew 0": ("READ_ADC", {"name": "ADCnew", "refs": 0}),
        "SET_PWM duty_cycle 1000 PWMoutpin 0-100%": (
            "SET_PWM", {"duty": "duty_cycle", "freq": 1000, "name": "PWMoutpin", "resolution": "0-100%"}),
        "UART_SEND var 1 0": ("UART_SEND", {"var": "var", "bytes": 1, "wait": 0}),
        "FORMATTED_STRING var value:\\x20\\\\3\\\\r\\\\n": (
            "FORMATTED_STRING", {"var": "var", "text": "value: \\3\\r\\n"}),
        "STRING dest var frmtString": ("STRING", {"dest": "dest", "var": "var", "text": "frmtString"}),
        "GOTO ?": ("GOTO", {"label": "?"}),
        "SLEEP $Tsleep 1000000": ("SLEEP", {"name": "$Tsleep", "delay": "1000000"}),
        "SEED_RANDOM Rand newSeed": ("SEED_RANDOM", {"name": "Rand", "seed": "newSeed"}),
        "16SEGMENTS dest src A": ("16SEGMENTS", {"dest": "dest", "src": "src", "common": "A"}),
        "QUAD_ENCOD qCount0 0 XqA0 XqB0 XqZ0 YqDir0 / 0": (
            "QUAD_ENCOD", {"counter": "qCount0", "int01": 0, "a": "XqA0", "b": "XqB0", "z": "XqZ0",
                           "dir": "YqDir0", "zkind": "/", "counts": 0}),
        "STEPPER step stepMax P 100 1 Ystep": (
            "STEPPER", {"name": "step", "max": "stepMax", "p": "P", "size": 100, "graph": 1, "coil": "Ystep"}),
        "NPULSE counter 1000 YNpulse": ("NPULSE", {"counter": "counter", "freq": 1000, "coil": "YNpulse"}),
        "I2C_RD I2C1 send recv Master 0 0 MSB 100000": (
            "I2C_RD", {"name": "I2C1", "send": "send", "recv": "recv", "mode": "Master", "address": "0",
                       "register": "0", "first": "MSB", "bitrate": "100000"}),
        "WSFR sfr srs": ("WSFR", {"sfr": "sfr", "src": "srs"}),
        "COMMENT --add comment here--": ("COMMENT", {"text": "--add comment here--", "line_ends": ()}),
        "PLACEHOLDER": ("PLACEHOLDER", {}),
    }
    for line, (kind, args) in expected.items():
        element = by_line[line]
        assert element.kind == kind, line
        assert element.args == args, line
        assert list(element.args) == [f.name for f in INSTRUCTIONS[kind].fields], line
    bus = by_line["BUS dest src 7 6 5 4 3 2 1 0"]
    assert list(bus.args.values())[2:] == [7, 6, 5, 4, 3, 2, 1, 0]  # the tokens in table order


def test_args_hold_every_field_in_table_order():
    for path in CORPUS_FILES:
        for _, element in load(path).elements():
            assert list(element.args) == [f.name for f in element.spec.fields], (rel(path), element)


def test_operands_keep_their_exact_tokens():
    program = load(CORPUS / "ldmicro" / "Tests" / "test-i2c-lcd16x2.ld")
    elements = [e for _, e in program.elements()]
    lut = elements[1]
    assert lut.args["values"] == ("72", "101", "108", "108", "111", "32", "33")
    assert lut.args["as_string"] == 1 and lut.args["table"] == "name"
    i2c = [e for e in elements if e.kind == "I2C_WR"]
    assert [e.args["send"] for e in i2c] == ["tab", "0xA0", "'0'"]
    assert i2c[0].args["address"] == "0x20"
    assert one("MOVE dest 0x1F").args == {"dest": "dest", "src": "0x1F"}
    assert one("LOOK_UP_TABLE d i 3 0 10 0x20 'A' t").args["values"] == ("10", "0x20", "'A'")


def test_header_values_of_5_4_files():
    program = load(EXPORT / "demo.ld")
    s = program.settings
    assert s == Settings(mcu="Atmel AVR ATmega328 28-PDIP", cycle_us=10000, crystal_hz=16000000,
                         baud=9600, cycle_timer=1, cycle_duty=False, config_word=0, spi_rate=1000000,
                         i2c_rate=100000, compiled=None, compiler="AVRGCC", ld_version="0.2")
    assert program.pullups == {"PB": 0xFF}
    assert program.var_sizes == {"Cparts": 2, "Tdly": 2}
    assert list(program.pins) == ["Xstart", "Xstop", "Ymotor", "Ylamp"]
    assert program.pins["Ymotor"] == PinAssignment("Ymotor", 14, 0, 0)
    lcd = load(CORPUS / "ldmicro" / "Tests" / "test-i2c-lcd16x2.ld")
    assert lcd.var_sizes["char7seg"] == 129 and lcd.var_sizes["char7seg[0]"] == 1
    assert lcd.settings.compiled.endswith("i2c-lcd16x2.c")
    spi = load(CORPUS / "ldmicro" / "Tests" / "test-spi.ld")
    assert list(spi.pins) == ["SPI_MOSI", "SPI_MISO", "SPI_SCK", "SPI__SS"]
    assert (spi.settings.spi_rate, spi.settings.i2c_rate) == (100000, 0)
    i2c = load(CORPUS / "ldmicro" / "Tests" / "test-i2c-1.ld")
    assert (i2c.settings.cycle_us, i2c.settings.cycle_timer) == (20000, 3)


def test_classic_io_list_and_defaults():
    program = load(SAMPLE / "coil_s_r_n.ld")
    assert program.pins == {}  # pin 0 = not assigned (and Xnew names are never remembered)
    assert program.settings.ld_version == "0.1"
    assert (program.settings.cycle_us, program.settings.cycle_timer) == (10000, 1)  # "CYCLE=10000 us"
    assert (program.settings.spi_rate, program.settings.i2c_rate) == (0, 0)  # "BAUD=9600 Hz"


# --- round trips --------------------------------------------------------------------------


@pytest.mark.parametrize("path", CORPUS_FILES, ids=rel)
def test_round_trip(path):
    program = load(path)
    text = write_ld(program)
    again, diagnostics = read_ld(text)
    assert diagnostics == [], [d.format("written") for d in diagnostics]
    assert again == program
    # and through the bytes LDmicro writes (CRLF, code page)
    again, diagnostics = read_ld_bytes(write_ld_bytes(program))
    assert diagnostics == [] and again == program


@pytest.mark.parametrize("path", CORPUS_FILES, ids=rel)
def test_round_trip_in_the_other_dialect(path):
    program = load(path)
    other = "0.1" if program.settings.ld_version == "0.2" else "0.2"
    again, diagnostics = read_ld(write_ld(program, other))
    assert diagnostics == []
    assert again.rungs == program.rungs  # long forms: the 0.1 adjust default never applies
    assert again.settings.ld_version == other


@pytest.mark.parametrize("name", WRITTEN_BY_54)
def test_program_section_as_ldmicro_5_4_writes_it(name):
    path = CORPUS / name
    original = path.read_bytes().decode("cp1252")
    assert "\t" not in "\n".join(program_section(original))
    written = write_ld(load(path))
    assert program_section(written) == program_section(original)


def test_demo_is_written_as_ldmicro_writes_it():
    original = (EXPORT / "demo.ld").read_text().splitlines()
    written = write_ld(load(EXPORT / "demo.ld"))
    lines = written.splitlines()
    # LDmicro writes a blank after each PULL-UP LIST entry; the corpus file has none
    assert "    PB: 0xFF \n" in written
    # and lists every I/O name, by type and name, as LDmicro 5.4.1.1 saves this file
    start, end = lines.index("IO LIST"), lines.index("PROGRAM")
    assert lines[start:end] == ["IO LIST", "    Xa at 0 0 0", "    Xb at 0 0 0", "    Xc at 0 0 0", "    Xe at 0 0 0",
                                "    Xstart at 4 0 0", "    Xstop at 5 0 0", "    Ylamp at 15 0 0",
                                "    Ymotor at 14 0 0", "    Yout at 0 0 0", "END", ""]
    rest = [line.rstrip() for line in lines[:start] + lines[end:]]
    assert rest == original[:original.index("IO LIST")] + original[original.index("PROGRAM"):]


def test_catalog_element_lines_are_5_4_long_forms():
    text = (EXPORT / "catalog.ld").read_text()
    written = write_ld(load(EXPORT / "catalog.ld"))
    strip = lambda lines: [line.strip() for line in lines if not line.startswith("RUNG")]
    assert strip(program_section(written)) == strip(program_section(text))


def test_written_0_1_form():
    program = load(EXPORT / "catalog.ld")
    program.var_sizes["x"] = 2
    program.settings.compiler = "AVRGCC"
    text = write_ld(program, "0.1")
    lines = text.splitlines()
    assert lines[0] == "LDmicro0.1"
    assert "VAR LIST" not in lines and "PULL-UP LIST" not in lines and "COMPILER=AVRGCC" not in lines
    assert lines.count("RUNG") == 113 and not any(re.match(r"RUNG \d", line) for line in lines)
    # long element forms even in 0.1 (§3.8)
    assert "  TON Tnew 100000 0" in lines and "  CTU Cnew 10 0 /" in lines
    assert "  COIL Ynew 0 0 0 1" in lines and "  UART_SEND var 1 0" in lines
    # FORMATTED_STRING as character codes, STRING as text
    text = "value: \\3\\r\\n"
    codes = " ".join(str(ord(c)) for c in text)
    assert f"  FORMATTED_STRING var {len(text)} {codes}" in lines
    assert "  STRING dest var frmtString" in lines


def test_written_element_lines_match_the_catalogue():
    expected = [
        "COIL Ynew 0 0 0 0", "CONTACTS Xnew 0 0", "TON Tnew 100000 0", "CTU Cnew 10 0 /",
        "SET_PWM duty_cycle 1000 PWMoutpin 0-100%", "FORMATTED_STRING var value:\\x20\\\\3\\\\r\\\\n",
        "READ_ADC ADCnew 0", "UART_RECV var 1 0", "SLEEP $Tsleep 1000000",
        "LOOK_UP_TABLE dest index 4 0 10 20 30 40 tabName",
        "PIECEWISE_LINEAR yvar xvar 2 0 0 10 100 name",
        "QUAD_ENCOD qCount0 0 XqA0 XqB0 XqZ0 YqDir0 / 0", "BUS dest src 7 6 5 4 3 2 1 0",
        "STRING dest var frmtString", "COMMENT --add comment here--", "PLACEHOLDER", "ODF",
    ]
    for line in expected:
        assert element_line(one(line)) == line


def test_writer_header_order_and_rung_numbers():
    program = Program(Settings(mcu="Microchip PIC16F877 40-PDIP", cycle_us=0, cycle_duty=True,
                               config_word=0x3F72, compiled="out.hex", compiler="HI_TECH_C"),
                      [Rung(Series([Element("CONTACTS", {"name": "Xa", "negated": 0, "set1": 0}),
                                    Parallel([Element("COIL", {"name": "Yb", "type": " "}),
                                              Series([Element("OSR", {}),
                                                      Element("COIL", {"name": "Yc", "type": "T"})])])])),
                       Rung(Series([]))],
                      {"Xa": PinAssignment("Xa", 2), "Ab": PinAssignment("Ab", "RE0"),
                       "Ic": PinAssignment("Ic", 3, 1, 100)},
                      {"Tx": 2}, {"PA": 0xFF})
    text = write_ld(program)
    assert text == (
        "LDmicro0.2\n"
        "MICRO=Microchip PIC16F877 40-PDIP\n"
        "CYCLE=0 us at Timer-1, YPlcCycleDuty:1, ConfigurationWord(s):0x3F72\n"
        "CRYSTAL=16000000 Hz\n"
        "BAUD=9600 Hz, RATE=1000000 Hz, SPEED=100000 Hz\n"
        "COMPILED=out.hex\n"
        "COMPILER=HI_TECH_C\n"
        "\n"
        "PULL-UP LIST\n"
        "    PA: 0xFF \n"
        "END\n"
        "\n"
        "VAR LIST\n"
        "    2 bytes Tx\n"
        "END\n"
        "\n"
        "IO LIST\n"
        "    Xa at 2 0 0\n"
        "    YPlcCycleDuty at 0 0 0\n"
        "    Yb at 0 0 0\n"
        "    Yc at 0 0 0\n"
        "    Ab at 8 0 0\n"  # RE0: a port bit is written as its package pin
        "    Ic at 3 1 100\n"
        "END\n"
        "\n"
        "PROGRAM\n"
        "RUNG 1\n"
        "  CONTACTS Xa 0 0\n"
        "  PARALLEL\n"
        "    COIL Yb 0 0 0 0\n"
        "    SERIES\n"
        "      OSR\n"
        "      COIL Yc 0 0 0 1\n"
        "    END\n"
        "  END\n"
        "END\n"
        "RUNG 2\n"
        "END\n"
    )
    again, diagnostics = read_ld(text)
    assert diagnostics == []
    assert again.settings.cycle_timer == -1  # cycle 0: free running
    program.settings.cycle_timer = -1
    program.pins["Ab"].pin = 8
    assert again == program
    data = write_ld_bytes(program)
    assert data.startswith(b"LDmicro0.2\r\nMICRO=") and b"\n" not in data.replace(b"\r\n", b"")


def test_writer_normalises_the_tree():
    el = lambda n: Element("CONTACTS", {"name": n, "negated": 0, "set1": 0})
    program = Program(rungs=[Rung(Series([Series([el("Xa")]), Parallel([Series([el("Xb")])]),
                                          Parallel([Parallel([el("Xc"), el("Xd")]), el("Xe")])]))])
    assert program_section(write_ld(program)) == [
        "PROGRAM", "RUNG 1", "  CONTACTS Xa 0 0", "  CONTACTS Xb 0 0", "  PARALLEL",
        "    CONTACTS Xc 0 0", "    CONTACTS Xd 0 0", "    CONTACTS Xe 0 0", "  END", "END"]


def test_comments_keep_line_breaks_and_blanks():
    element = one("COMMENT first\\r\\nsecond line  with  blanks\\r\\n")
    assert element.args["text"] == "first\nsecond line  with  blanks\n"
    assert element_line(element) == "COMMENT first\\r\\nsecond line  with  blanks\\r\\n"
    # a lone CR stays what it is; blanks ending a line are kept apart (the drawing, like
    # LDmicro's export, cannot show them) and written back
    for text in ["a\rb", " leading", "back\\slash", "tab\there", "", "(none)"]:
        line = element_line(Element("COMMENT", {"text": text, "line_ends": ()}))
        assert one(line).args["text"] == text, line
    blanks = one("COMMENT ends in blanks\\x20\\x20\\r\\nnext  ")
    assert blanks.args == {"text": "ends in blanks\nnext", "line_ends": ("2", "0")}
    assert element_line(blanks) == "COMMENT ends in blanks  \\r\\nnext"  # as LDmicro writes them
    assert one("COMMENT (none)").args["text"] == ""


def test_non_ascii_text_round_trips_through_bytes():
    program = Program(rungs=[Rung(Series([Element("COMMENT", {"text": "Température €\nsuite", "line_ends": ()})])),
                             Rung(Series([Element("FORMATTED_STRING", {"var": "v", "text": "°C é"})]))])
    for version in ("0.2", "0.1"):
        data = write_ld_bytes(program, version=version)
        assert b"Temp\xe9rature \x80\\r\\nsuite" in data
        again, diagnostics = read_ld_bytes(data)
        assert diagnostics == []
        assert again.rungs == program.rungs
    # LDmicro 5.4.1.1's own sign-extended escape reads as the byte
    assert one("COMMENT caf\\xFFFFFFE9").args["text"] == "café"


def test_text_that_looks_like_character_codes_is_protected():
    for text in ["3 items", "0", "-5 degrees", "12", "(none)"]:
        element = Element("FORMATTED_STRING", {"var": "v", "text": text})
        line = element_line(element)
        assert not re.match(r"FORMATTED_STRING v [+-]?\d", line), line
        assert one(line).args["text"] == text
        string = Element("STRING", {"dest": "d", "var": "", "text": text})
        assert one(element_line(string)).args == {"dest": "d", "var": "", "text": text}
    # a 0.2 text starting with a digit (as LDmicro 5.4 writes it) is still read as text
    assert one("FORMATTED_STRING v 3\\x20items").args["text"] == "3 items"


def test_long_lines_are_reported_not_silent():
    program = Program(rungs=[Rung(Series([Element("COMMENT", {"text": "x" * 600, "line_ends": ()})]))],
                      pins={"X" + "n" * 70: PinAssignment("X" + "n" * 70, 5)})
    diagnostics = []
    text = write_ld(program, diagnostics=diagnostics)
    assert "x" * 600 in text  # written anyway
    assert len(diagnostics) == 2 and all(d.severity == WARNING for d in diagnostics)
    assert "511" in diagnostics[1].message and "63" in diagnostics[0].message
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # never a raw Python warning, with or without a list
        write_ld(program)
        write_ld(load(EXPORT / "catalog.ld"))


def test_bad_version_argument():
    with pytest.raises(ValueError):
        write_ld(Program(), "0.3")


# --- legacy forms and defaults (§2, §3.7) -----------------------------------------------------


@pytest.mark.parametrize("kind", ["TON", "TOF", "RTO"])
def test_timer_adjust_default_depends_on_the_dialect(kind):
    assert one(f"{kind} Tx 500000", "0.1").args == {"name": "Tx", "delay": 500000, "adjust": -1}
    assert one(f"{kind} Tx 500000", "0.2").args == {"name": "Tx", "delay": 500000, "adjust": 0}
    assert one(f"{kind} Tx 500000 3", "0.1").args["adjust"] == 3


@pytest.mark.parametrize("kind", ["RTL", "TCY", "THI", "TLO"])
def test_newer_timers_default_adjust_is_zero(kind):
    assert one(f"{kind} Tx 100", "0.1").args == {"name": "Tx", "delay": 100, "adjust": 0}


def test_timer_delay_is_microseconds_or_a_variable():
    assert one("TON Tx delayVar 0").args["delay"] == "delayVar"
    # LDmicro 5.4 writes TIME2COUNT's adjust, older files have none: both are kept as they are
    assert one("TIME2COUNT Tx 250").args == {"name": "Tx", "delay": 250, "adjust": None}
    assert one("TIME2COUNT Tx 250 0").args == {"name": "Tx", "delay": 250, "adjust": 0}
    assert one("DELAY 10").args == {"delay": "10"}


def test_counter_short_forms():
    assert one("CTU Cx 10").args == {"name": "Cx", "max": "10", "init": "0", "kind": "/"}
    assert one("CTD Cx -5 2").args == {"name": "Cx", "max": "-5", "init": "2", "kind": "/"}
    assert one("CTC Cx 9 0 o").args["kind"] == "o"


def test_set_pwm_legacy_forms():
    assert one("SET_PWM duty 10000").args == {"duty": "duty", "freq": 10000, "name": "P", "resolution": ""}
    assert one("SET_PWM duty 2000 led").args["name"] == "Pled"
    assert one("SET_PWM duty 2000 Pled").args["name"] == "Pled"
    assert one("SET_PWM cycle 1200.75 Pled 0-100% (6.7 bits)").args == {
        "duty": "cycle", "freq": 1200, "name": "Pled", "resolution": "0-100%"}
    program = load(CORPUS / "ldmicro" / "reg" / "tests" / "misc-ops.ld")
    pwm = [e for _, e in program.elements() if e.kind == "SET_PWM"]
    assert pwm[0].args == {"duty": "duty", "freq": 10000, "name": "P", "resolution": ""}
    assert element_line(pwm[0]) == "SET_PWM duty 10000 P "  # as LDmicro 5.4 saves it again


def test_contacts_and_coil_short_forms():
    assert one("CONTACTS Xa 1").args == {"name": "Xa", "negated": 1, "set1": 0}
    assert one("CONTACTS Xa 0 1").args == {"name": "Xa", "negated": 0, "set1": 1}
    for flags, coil_type in [("0 0 0", " "), ("1 0 0", "/"), ("0 1 0", "S"), ("0 0 1", "R"),
                             ("0 0 0 0", " "), ("0 0 0 1", "T"), ("1 1 0 0", "/"), ("0 1 1 1", "S"),
                             ("0 0 1 1", "R"), ("0 0 2 0", "R")]:
        assert one(f"COIL Ya {flags}").args == {"name": "Ya", "type": coil_type}, flags


def test_uart_adc_aliases_and_bare_keywords():
    assert one("UART_SEND ch").args == {"var": "ch", "bytes": 1, "wait": 0}
    assert one("UART_RECV ch").args == {"var": "ch", "bytes": 1, "wait": 0}
    assert one("UART_RECV ch 2 1").args == {"var": "ch", "bytes": 2, "wait": 1}
    assert one("READ_ADC Ain").args == {"name": "Ain", "refs": 0}
    assert one("OSL").kind == "ODF"
    assert one("UART_SEND_BUSY").kind == "UART_SEND_READY"
    assert one("UART_UDRE").kind == "UART_SEND_READY"
    assert one("SLEEP").args == {"name": "", "delay": ""}
    assert element_line(one("SLEEP")) == "SLEEP  "  # LDmicro 5.4 writes both operands, empty ones too


def test_formatted_string_forms():
    # 0.1 numeric form; codes below 32 become 'X'
    assert one("FORMATTED_STRING cnt 5 72 105 13 10 33", "0.1").args == {"var": "cnt", "text": "HiXX!"}
    assert one("FORMATTED_STRING (none) 0").args == {"var": "", "text": ""}
    assert one("FORMATTED_STRING (none) (none)").args == {"var": "", "text": ""}
    hello = load(SAMPLE / "hello.ld")
    fs = [e for _, e in hello.elements() if e.kind == "FORMATTED_STRING"][0]
    assert fs.args == {"var": "cnt", "text": "Hello, world: \\-5\\r\\n"}
    uart = load(CORPUS / "ldmicro" / "Tests" / "test-uart.ld")  # numeric form in a 0.2 file
    assert [e for _, e in uart.elements() if e.kind == "FORMATTED_STRING"][0].args["text"] == "Hello !"
    # 0.2 text form: escapes decoded, the user's own backslashes kept, line feeds dropped
    assert one("FORMATTED_STRING v a\\x20b\\\\n\\n").args == {"var": "v", "text": "a b\\n"}
    assert one("STRING (none) v %d\\x20units").args == {"dest": "", "var": "v", "text": "%d units"}


def test_look_up_table_and_piecewise_linear_legacy_names():
    program = load(CORPUS / "ldmicro" / "reg" / "tests" / "misc-ops.ld")
    lut = [e for _, e in program.elements() if e.kind == "LOOK_UP_TABLE"][0]
    assert lut.args == {"dest": "duty", "index": "Ci", "values": ("10", "70", "80", "70", "10"),
                        "as_string": 0, "table": "duty5"}
    assert one("PIECEWISE_LINEAR y x 2 0 0 10 100").args == {
        "dest": "y", "index": "x", "points": (("0", "0"), ("10", "100")), "table": ""}
    assert element_line(one("PIECEWISE_LINEAR y x 2 0 0 10 100")) == "PIECEWISE_LINEAR y x 2 0 0 10 100 "
    assert one("LOOK_UP_TABLE d i 0 0").args["values"] == ()


def test_quad_encoder_optional_pins():
    assert one("QUAD_ENCOD q 0 Xa Xb (none) (none) / 100").args == {
        "counter": "q", "int01": 0, "a": "Xa", "b": "Xb", "z": "", "dir": "", "zkind": "/", "counts": 100}
    assert element_line(one("QUAD_ENCOD q 0 Xa Xb (none) (none) / 100")) == \
        "QUAD_ENCOD q 0 Xa Xb (none) (none) / 100"


def test_header_forms():
    def settings_of(header: str) -> Settings:
        program, diagnostics = read_ld(f"LDmicro0.2\n{header}\nPROGRAM\n")
        assert diagnostics == [], [d.message for d in diagnostics]
        return program.settings

    assert settings_of("BAUD=2400 Hz, RATE=0 Hz").baud == 2400
    s = settings_of("BAUD=2400 Hz, RATE=500 Hz")
    assert (s.spi_rate, s.i2c_rate) == (500, 0)
    s = settings_of("BAUD=2400")
    assert (s.baud, s.spi_rate, s.i2c_rate) == (2400, 0, 0)
    s = settings_of("CYCLE=1000 us at Timer0, YPlcCycleDuty:1")
    assert (s.cycle_us, s.cycle_timer, s.cycle_duty, s.config_word) == (1000, 0, True, 0)
    assert settings_of("CYCLE=1000 us at Timer2, YPlcCycleDuty:0").cycle_timer == 1
    assert settings_of("CYCLE=0 us at Timer1, YPlcCycleDuty:0, ConfigurationWord(s):0x0").cycle_timer == -1
    assert settings_of("CYCLE=5000 us at Timer1, YPlcCycleDuty:0, WDTE:1").cycle_us == 5000
    assert settings_of("CYCLE=500 us at Timer1, YPlcCycleDuty:0, ConfigurationWord(s):0x3F32").config_word == 0x3F32
    s = settings_of("CYCLE=50000")
    assert (s.cycle_us, s.cycle_timer, s.cycle_duty) == (50000, 1, False)
    assert settings_of("CRYSTAL=4000000").crystal_hz == 4000000
    assert settings_of("MICRO=Atmel AVR ATmega8 28-PDIP").mcu == "Atmel AVR ATmega8 28-PDIP"
    assert settings_of("COMPILER=ARDUINO").compiler == "ARDUINO"
    program, diagnostics = read_ld("LDmicro0.3\nPROGRAM\n")
    assert program.settings.ld_version == "0.2" and [d.severity for d in diagnostics] == [WARNING]


def test_lists():
    text = ("LDmicro0.2\nMICRO=Atmel AVR ATmega16 40-PDIP\n\nPULL-UP LIST\n    PA: 0x0F \n    PB: 0xFF\nEND\n"
            "\nVAR LIST\n    2 bytes Ca \tNow not used !!!\n  129 bytes tab\n  cnt signed 16 bit variable\nEND\n"
            "\nIO LIST\n    Xa at 2\n    Yb at 3 0 0\n    Hreg at 0 1 40001\n    Mcoil at 7 2 17\n"
            "    Xnew at 4\n    Xc at 0\n    I2C1_SCL at 139 0 0\nEND\n\nPROGRAM\n")
    program, diagnostics = read_ld(text)
    assert diagnostics == []
    assert program.pullups == {"PA": 0x0F, "PB": 0xFF}
    assert program.var_sizes == {"Ca": 2, "tab": 129, "cnt": 2}
    assert program.pins == {"Xa": PinAssignment("Xa", 2), "Yb": PinAssignment("Yb", 3),
                            "Hreg": PinAssignment("Hreg", 0, 1, 40001), "Mcoil": PinAssignment("Mcoil", 7, 2, 17),
                            "I2C1_SCL": PinAssignment("I2C1_SCL", 139)}
    # without MICRO= the pull-ups are not applied
    program, diagnostics = read_ld("LDmicro0.2\nPULL-UP LIST\n    PB: 0xFF\nEND\nPROGRAM\n")
    assert program.pullups == {} and [d.severity for d in diagnostics] == [WARNING]


# --- bad input: located diagnostics, never an exception -----------------------------------------


def located(text: str) -> list[tuple[str, str, int, int]]:
    program, diagnostics = read_ld(text)
    return [(d.severity, d.code, d.span.line, d.span.col) for d in diagnostics]


def test_unknown_keyword_keeps_the_rest():
    program, diagnostics = read_ld(ld("RUNG 1\n  FROB a b\n  CONTACTS Xa 0 0\n  COIL Yb 0 0 0 0\nEND\n"))
    (d,) = diagnostics
    assert (d.severity, d.code, d.span.line, d.span.col, d.span.end_col) == (ERROR, LD_SYNTAX, 3, 2, 6)
    assert "FROB a b" in d.message
    assert [e.kind for e in program.rungs[0].elements()] == ["CONTACTS", "COIL"]


def test_missing_fields_and_bad_numbers():
    text = ld("RUNG 1\n  TON Tx\n  COIL Ya 0 0\n  CTU Cx 10 0 q\n  SET_PWM d 1k Pa\n"
              "  READ_ADC Ax two\n  LOOK_UP_TABLE d i 3 0 1 2\n  PIECEWISE_LINEAR y x 2 0 0 1\n"
              "  FORMATTED_STRING v 3 65 66\n  CONTACTS Xa 0 0\nEND\n")
    program, diagnostics = read_ld(text)
    assert [(d.code, d.span.line) for d in diagnostics] == [
        (LD_SYNTAX, 3), (LD_SYNTAX, 4), (LD_SYNTAX, 5), (BAD_VALUE, 6), (BAD_VALUE, 7), (LD_SYNTAX, 8),
        (LD_SYNTAX, 9), (LD_SYNTAX, 10)]
    assert all(d.severity == ERROR for d in diagnostics)
    assert diagnostics[0].span.col == len("  TON Tx")  # missing operand: the end of the line
    assert diagnostics[3].span.col == len("  SET_PWM d ")  # the bad token
    assert "'TON Tx'" in diagnostics[0].message and "'READ_ADC Ax two'" in diagnostics[4].message
    assert [e.kind for e in program.rungs[0].elements()] == ["CONTACTS"]


def test_parallel_directly_inside_parallel():
    text = ld("RUNG 1\n  PARALLEL\n    PARALLEL\n      CONTACTS Xa 0 0\n      CONTACTS Xb 0 0\n    END\n"
              "    CONTACTS Xc 0 0\n  END\n  COIL Yd 0 0 0 0\nEND\n")
    program, diagnostics = read_ld(text)
    assert located(text) == [(ERROR, LD_SYNTAX, 4, 4)]
    branches = program.rungs[0].circuit.items[0].branches  # read anyway, normalised
    assert [b.args["name"] for b in branches] == ["Xa", "Xb", "Xc"]


def test_unclosed_blocks():
    text = ld("RUNG 1\n  PARALLEL\n    CONTACTS Xa 0 0\n    SERIES\n      CONTACTS Xb 0 0\n")
    program, diagnostics = read_ld(text)
    assert [(d.span.line, d.span.col) for d in diagnostics] == [(2, 0), (3, 2), (5, 4)]
    assert all("not closed" in d.message for d in diagnostics)
    assert program.rungs[0].circuit.items[0] == Parallel(
        [Element("CONTACTS", {"name": "Xa", "negated": 0, "set1": 0}),
         Element("CONTACTS", {"name": "Xb", "negated": 0, "set1": 0})])
    # a rung left open before the next RUNG line: both rungs are read
    text = ld("RUNG 1\n  CONTACTS Xa 0 0\nRUNG 2\n  COIL Yb 0 0 0 0\nEND\n")
    program, diagnostics = read_ld(text)
    assert located(text) == [(ERROR, LD_SYNTAX, 2, 0)]
    assert len(program.rungs) == 2


def test_stray_lines_between_rungs():
    text = ld("RUNG 1\nEND\n  CONTACTS Xa 0 0\n; note\nEND\nRUNG 2\nEND\n")
    assert located(text) == [(ERROR, LD_SYNTAX, 4, 2), (ERROR, LD_SYNTAX, 5, 0), (ERROR, LD_SYNTAX, 6, 0)]
    program, _ = read_ld(text)
    assert len(program.rungs) == 2


def test_semicolon_lines_inside_a_rung_are_skipped():
    program, diagnostics = read_ld(ld("RUNG 1\n  ; a note\n  CONTACTS Xa 0 0\nEND\n"))
    assert diagnostics == [] and len(list(program.rungs[0].elements())) == 1


def test_too_many_entries_in_one_series():
    body = "".join(f"  CONTACTS X{i} 0 0\n" for i in range(64))
    text = ld(f"RUNG 1\n{body}END\n")
    assert located(text) == [(ERROR, LD_SYNTAX, 3 + 63, 2)]


def test_header_problems():
    text = "  LDmicro0.2\nCRYSTAL=fast\nVAR LIST\n  two bytes x\nEND\nPROGRAM\n"
    program, diagnostics = read_ld(text)
    assert [(d.severity, d.span.line) for d in diagnostics] == [(WARNING, 0), (WARNING, 0), (ERROR, 1), (ERROR, 3)]
    assert "'CRYSTAL=fast'" in diagnostics[2].message
    assert program.settings.crystal_hz == 16000000


def test_not_an_ld_file():
    for text in ["", "hello\nworld\n", "\x00\x01\x02\xff\n\x00"]:
        program, diagnostics = read_ld(text)
        assert program.rungs == []
        assert [d.code for d in diagnostics if d.severity == ERROR] == [UNREADABLE]
    program, diagnostics = read_ld_bytes(bytes(range(256)) * 4)
    assert any(d.code == UNREADABLE for d in diagnostics)


def test_long_names_are_rejected():
    assert [d.code for d in errors(ld(f"RUNG 1\n  CONTACTS X{'a' * 70} 0 0\nEND\n"))] == [BAD_VALUE]
    too_many = " ".join(["1"] * 65)
    assert [d.code for d in errors(ld(f"RUNG 1\n  LOOK_UP_TABLE d i 65 0 {too_many} t\nEND\n"))] == [BAD_VALUE]


def test_lines_end_in_crlf_or_lf_and_trailing_blanks_go():
    text = "LDmicro0.1\r\nPROGRAM\r\nRUNG  \r\n\tCONTACTS Xa 1 \t\r\n\r\n    COIL Yb 0 0 0\r\nEND\r\n"
    program, diagnostics = read_ld(text)
    assert diagnostics == []
    assert [e.args["name"] for e in program.rungs[0].elements()] == ["Xa", "Yb"]


# --- property tests --------------------------------------------------------------------------------

CORPUS_TEXTS = [path.read_bytes().decode("cp1252") for path in CORPUS_FILES]
WORDS = ["RUNG", "RUNG 1", "END", "PARALLEL", "SERIES", "PROGRAM", "IO LIST", "VAR LIST",
         "PULL-UP LIST", "LDmicro0.1", "LDmicro0.2", "CONTACTS Xa 0 0", "COIL Yb 0 0 0", "TON T 1",
         "COMMENT hi\\r\\nthere", "FORMATTED_STRING v 2 65", "LOOK_UP_TABLE d i 2 0 1", ";", "CYCLE=",
         "BAUD=1 Hz", "    Xa at 3", "  2 bytes v", " ", "\t", "\n", "\r\n", "\x00", "é", "\\x"]


def check_reading(text: str) -> Program:
    program, diagnostics = read_ld(text)
    line_count = text.count("\n") + 1
    for d in diagnostics:
        assert "internal error" not in d.message, d.message
        assert "cannot read the file" not in d.message, d.message  # the grammar accepts any text
        assert d.span is not None and 0 <= d.span.line <= line_count, d
    for _, element in program.elements():
        assert element.span is not None
    return program


def check_written(program: Program) -> None:
    again, diagnostics = read_ld(write_ld(program))
    assert [d for d in diagnostics if d.severity == ERROR] == []
    assert again == program


@settings(deadline=None, derandomize=True, max_examples=200)
@given(st.text())
def test_random_text_never_raises(text):
    check_reading(text)


@settings(deadline=None, derandomize=True, max_examples=200)
@given(st.binary())
def test_random_bytes_never_raise(data):
    program, diagnostics = read_ld_bytes(data)
    assert all("internal error" not in d.message and "cannot read the file" not in d.message
               for d in diagnostics)


@settings(deadline=None, derandomize=True, max_examples=200)
@given(st.lists(st.sampled_from(WORDS) | st.text(max_size=8), max_size=60))
def test_structure_words_never_raise(parts):
    text = "".join(part + ("\n" if i % 3 == 0 else " ") for i, part in enumerate(parts))
    program = check_reading(text)
    check_written(program)


@st.composite
def mutated_corpus_file(draw):
    lines = draw(st.sampled_from(CORPUS_TEXTS)).splitlines()
    for _ in range(draw(st.integers(1, 5))):
        index = draw(st.integers(0, max(len(lines) - 1, 0)))
        action = draw(st.sampled_from(["delete", "duplicate", "token", "insert", "truncate", "swap", "chars"]))
        if not lines:
            lines.append(draw(st.text(max_size=20)))
        elif action == "delete":
            del lines[index]
        elif action == "duplicate":
            lines.insert(index, lines[index])
        elif action == "token":
            tokens = lines[index].split(" ")
            position = draw(st.integers(0, len(tokens) - 1))
            tokens[position] = draw(st.sampled_from(WORDS) | st.text(max_size=6))
            lines[index] = " ".join(tokens)
        elif action == "insert":
            lines.insert(index, draw(st.sampled_from(WORDS) | st.text(max_size=30)))
        elif action == "truncate":
            lines = lines[:index]
        elif action == "swap":
            other = draw(st.integers(0, len(lines) - 1))
            lines[index], lines[other] = lines[other], lines[index]
        else:
            line = lines[index]
            cut = draw(st.integers(0, len(line)))
            lines[index] = line[:cut] + draw(st.text(max_size=3)) + line[cut + 1:]
    return "\n".join(lines)


@settings(deadline=None, derandomize=True, max_examples=200)
@given(mutated_corpus_file())
def test_mutated_corpus_files_never_raise(text):
    program = check_reading(text)
    check_written(program)


def test_every_corpus_line_mutated_by_one_token():
    """Deterministic sweep: drop the last token of every PROGRAM line of a few files."""
    rng = random.Random(7)
    for path in [SAMPLE / "traffic.ld", EXPORT / "catalog.ld", CORPUS / "ldmicro" / "Tests" / "test-spi.ld"]:
        lines = path.read_text().splitlines()
        start = lines.index("PROGRAM")
        for index in range(start + 1, len(lines)):
            mutated = list(lines)
            mutated[index] = " ".join(lines[index].split()[:-1] or [rng.choice(WORDS)])
            check_reading("\n".join(mutated))


def test_a_control_character_the_01_dialect_cannot_keep_is_said():
    # LDmicro0.1 stores a formatted string as character codes and reads those below 32 as 'X'
    program, _ = read_ld("LDmicro0.2\nPROGRAM\nRUNG 1\n  FORMATTED_STRING (none) a\\tb\nEND\n")
    said = []
    text = write_ld(program, version="0.1", diagnostics=said)
    assert "FORMATTED_STRING (none) 3 97 9 98" in text
    assert [d.code for d in said] == ["LD009"] and "read as 'X'" not in said[0].message and "0x09" in said[0].message
    write_ld(program, diagnostics=said)
    assert len(said) == 1  # the 0.2 dialect keeps it
