""".ld -> .ladder -> .ld, byte for byte (README, "LDmicro's files").

The writer writes the form of LDmicro 5.4.1.1's own writer (`SaveProjectToFile`):
a file in that form comes back unchanged, any other file comes back in that
form. `RULES` rewrites a file into that form one named normalisation at a
time: the list the README gives, checked here on every corpus file. The corpus
keeps LDmicro's files with LF line ends, as LDmicro's git repository does;
LDmicro writes CRLF, and so do `ladder convert` and `write_ld_bytes`."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from corpus import CORPUS, all_ld_files

from lang.diagnostics import ERROR
from lang.iolist import io_list
from lang.ldfile import write_ld_bytes
from lang.loader import load_bytes
from lang.textform.writer import render_program


def rel(path: Path) -> str:
    return path.relative_to(CORPUS).as_posix()


def through_the_text_form(data: bytes) -> bytes:
    """What `ladder convert x.ld y.ladder` then `ladder convert y.ladder z.ld` write."""
    ld = load_bytes(data, "x.ld")
    assert not [d for d in ld.diagnostics if d.severity == ERROR]
    ladder = load_bytes(render_program(ld.program).encode("utf-8"), "y.ladder")
    assert not [d for d in ladder.diagnostics if d.severity == ERROR]
    return write_ld_bytes(ladder.program)


def lines_of(path: Path) -> list[str]:
    return path.read_bytes().decode("cp1252").split("\n")


def in_the_5x_format(path: Path) -> bool:
    """An LDmicro0.2 (or bare LDmicro) file with a 5.x CYCLE line."""
    lines = lines_of(path)
    cycle = next((line for line in lines if line.startswith("CYCLE=")), "")
    return lines[0] in ("LDmicro0.2", "LDmicro") and " us at Timer" in cycle


FORMAT_5X = [path for path in all_ld_files() if in_the_5x_format(path)]


# --- the normalisations -----------------------------------------------------------------------
# Each takes and returns a file's lines (split at LF, the last one empty). The
# corpus files have one blank line before each section and before PROGRAM.


def _dialect_01(lines: list[str]) -> bool:
    return lines[0] == "LDmicro0.1"


def _header_line(line: str) -> str:
    key, _, value = line.partition("=")
    if key == "CYCLE":
        us, timer, duty, word = re.fullmatch(
            r"(\d+)(?: us(?: at Timer(\d+), YPlcCycleDuty:(\d)(?:, ConfigurationWord\(s\):0x(\w+))?)?)?",
            value).groups()
        timer = -1 if us == "0" else timer or 1
        return f"CYCLE={us} us at Timer{timer}, YPlcCycleDuty:{duty or 0}, ConfigurationWord(s):0x{word or 0}"
    if key == "CRYSTAL":
        return f"CRYSTAL={value.removesuffix(' Hz')} Hz"
    if key == "BAUD":  # LDmicro reads a missing RATE or SPEED as 0
        baud, rate, speed = re.fullmatch(r"(\d+)(?: Hz(?:, RATE=(\d+) Hz(?:, SPEED=(\d+) Hz)?)?)?", value).groups()
        return f"BAUD={baud} Hz, RATE={rate or 0} Hz, SPEED={speed or 0} Hz"
    return line


def header_lines_in_full(lines: list[str]) -> list[str]:
    end = lines.index("")
    header = [_header_line(line) for line in lines[:end]]
    if not any(line.startswith("BAUD=") for line in header):  # LDmicro's defaults
        crystal = next(i for i, line in enumerate(header) if line.startswith("CRYSTAL="))
        header.insert(crystal + 1, "BAUD=9600 Hz, RATE=1000000 Hz, SPEED=100000 Hz")
    return header + lines[end:]


def _section(lines: list[str], title: str) -> tuple[int, int]:
    """The indexes of a section's title and of its END."""
    start = lines.index(title)
    return start, lines.index("END", start)


def sections_of_the_dialect(lines: list[str]) -> list[str]:
    """0.2: PULL-UP LIST, VAR LIST, IO LIST, added empty where missing; 0.1: IO LIST only."""
    if _dialect_01(lines):
        if "VAR LIST" not in lines:
            return lines
        start, end = _section(lines, "VAR LIST")
        return lines[:start - 1] + lines[end + 1:]  # with the blank line before it
    for title, before in (("PULL-UP LIST", "VAR LIST"), ("VAR LIST", "IO LIST")):
        if title not in lines:
            at = lines.index(before if before in lines else "IO LIST") - 1
            lines = lines[:at] + ["", title, "END"] + lines[at:]
    return lines


def _entries(lines: list[str], title: str, rewrite) -> list[str]:
    """Each entry of a section rewritten; those rewritten to None go."""
    if title not in lines:
        return lines
    start, end = _section(lines, title)
    entries = [rewrite(line) for line in lines[start + 1:end]]
    return lines[:start + 1] + [line for line in entries if line is not None] + lines[end:]


def pullup_lines_end_in_a_blank(lines: list[str]) -> list[str]:
    return _entries(lines, "PULL-UP LIST", lambda line: f"    {line.strip()} ")


def var_list_lines_in_full(lines: list[str]) -> list[str]:
    def rewrite(line: str) -> str:
        size, name, note = re.match(r"\s*(\d+) bytes (\S+)(.*)", line).groups()
        return f"  {int(size):3d} bytes {name}{note if note.strip() else ''}"
    return _entries(lines, "VAR LIST", rewrite)


def io_list_as_ldmicro_writes_it(lines: list[str]) -> list[str]:
    """Every I/O name the program uses, assigned or not (`at 0 0 0`), by
    LDmicro's I/O type, then by name; a pin in full (`Xa at 2` -> `Xa at 2 0
    0`); a 0.1 file lists X, Y and A names and assigned pins only. Which names and types the
    drawing gives is lang.iolist's: LDmicro's own saves check that list
    (test_ldmicro_saves)."""
    start, end = _section(lines, "IO LIST")
    assigned = {}
    for line in lines[start + 1:end]:
        name, pin, slave, register = re.fullmatch(r"\s*(\S+) at (\S+)(?: (\d+) (\d+))?", line).groups()
        if name[1:] != "new" and (pin, slave or "0", register or "0") != ("0", "0", "0"):
            assigned[name] = f"{pin} {slave or 0} {register or 0}" if pin.isdigit() else pin
    program = load_bytes("\n".join(lines).encode("cp1252"), "x.ld").program
    listed = [io.name for io in io_list(program) if not _dialect_01(lines) or io.name[0] in "XYA" or io.name in assigned]
    return lines[:start + 1] + [f"    {name} at {assigned.get(name, '0 0 0')}" for name in listed] + lines[end:]


def _program(lines: list[str]) -> tuple[list[str], list[str]]:
    """The lines up to PROGRAM, and the program's lines."""
    start = lines.index("PROGRAM") + 1
    return lines[:start], lines[start:-1]


def single_element_blocks_dropped(lines: list[str]) -> list[str]:
    head, body = _program(lines)
    words = [line.strip() for line in body]
    out, index = [], 0
    while index < len(body):
        single = (words[index] in ("SERIES", "PARALLEL") and words[index + 2:index + 3] == ["END"]
                  and words[index + 1] not in ("SERIES", "PARALLEL", "END"))
        out.append(body[index + 1] if single else body[index])
        index += 3 if single else 1
    return head + out + [""]


def rungs_numbered_two_blanks_a_level(lines: list[str]) -> list[str]:
    head, body = _program(lines)
    out, depth, rung = [], 0, 0
    for line in (line.strip() for line in body):
        if line.startswith("RUNG"):
            rung += 1
            out.append("RUNG" if _dialect_01(lines) else f"RUNG {rung}")
            depth = 1
            continue
        depth -= line == "END"
        out.append("  " * depth + line)
        depth += line in ("SERIES", "PARALLEL")
    return head + out + [""]


def _missing_operands(keyword: str, operands: list[str], dialect_01: bool) -> list[str]:
    """What LDmicro reads for the operands a short form leaves out (ldmicro-formats.md §2)."""
    counters = ("CTU", "CTD", "CTC", "CTR")
    missing = {("CONTACTS", 2): ["0"], ("COIL", 4): ["0"], ("READ_ADC", 1): ["0"],
               ("UART_SEND", 1): ["1", "0"], ("UART_RECV", 1): ["1", "0"], ("SET_PWM", 2): ["P", ""],
               **{(kind, 2): ["-1" if dialect_01 else "0"] for kind in ("TON", "TOF", "RTO")},
               **{(kind, 2): ["0", "/"] for kind in counters}, **{(kind, 3): ["/"] for kind in counters}}
    if keyword == "LOOK_UP_TABLE" and len(operands) == 4 + int(operands[2]):
        return [operands[0] + operands[2]]  # the table is named after its destination and size
    return missing.get((keyword, len(operands)), [])


def element_lines_in_long_form(lines: list[str]) -> list[str]:
    head, body = _program(lines)
    out = []
    for line in body:
        text = line.lstrip()
        keyword, *operands = text.split(" ")
        if keyword != "COMMENT":
            operands += _missing_operands(keyword, operands, _dialect_01(lines))
            line = line[:len(line) - len(text)] + " ".join([keyword] + operands)
        out.append(line)
    return head + out + [""]


def formatted_strings_as_text(lines: list[str]) -> list[str]:
    """A 0.2 file's FORMATTED_STRING in character codes (an older 5.x wrote them)."""
    if _dialect_01(lines):
        return lines

    def as_text(match: re.Match) -> str:
        text = "".join(chr(int(code)) for code in match.group(2).split()[1:])
        return match.group(1) + text.replace("\\", "\\\\").replace(" ", "\\x20")
    return [re.sub(r"^(\s*FORMATTED_STRING \S+ )(\d+(?: \d+)*)$", as_text, line) for line in lines]


RULES = [header_lines_in_full, sections_of_the_dialect, pullup_lines_end_in_a_blank,
         var_list_lines_in_full, io_list_as_ldmicro_writes_it, single_element_blocks_dropped,
         rungs_numbered_two_blanks_a_level, element_lines_in_long_form, formatted_strings_as_text]


def in_54_form(path: Path) -> tuple[bytes, list[str]]:
    """The file in the form LDmicro 5.4.1.1 writes (CRLF), and the rules that changed it."""
    lines, applied = lines_of(path), []
    for rule in RULES:
        rewritten = rule(lines)
        if rewritten != lines:
            applied.append(rule.__name__)
        lines = rewritten
    return "\r\n".join(lines).encode("cp1252"), applied


# --- the tests --------------------------------------------------------------------------------


def test_the_corpus_has_nineteen_files_in_the_5x_format():
    assert len(FORMAT_5X) == 19


@pytest.mark.parametrize("path", all_ld_files(), ids=rel)
def test_every_file_comes_back_exactly_normalised(path):
    expected, _ = in_54_form(path)
    assert through_the_text_form(path.read_bytes()) == expected


@pytest.mark.parametrize("path", FORMAT_5X, ids=rel)
def test_a_file_in_54s_form_comes_back_byte_for_byte(path):
    as_written, _ = in_54_form(path)
    assert through_the_text_form(as_written) == as_written


def test_the_corpus_file_ldmicro_54_wrote_as_it_is_comes_back_byte_for_byte():
    """Tests/test-leds.ld is 5.4's "Save as 0.1" form: it needs none of RULES."""
    path = CORPUS / "ldmicro" / "Tests" / "test-leds.ld"
    as_written = path.read_bytes().replace(b"\n", b"\r\n")
    assert in_54_form(path) == (as_written, [])
    assert through_the_text_form(as_written) == as_written


# Why no corpus file in the 5.x format comes back as it is stored, even with
# CRLF line ends: an LDmicro older than 5.4.1.1 (or a person) wrote each.
# ldmicro-export/ holds copies of the first eight under other names.
NOT_IN_54_FORM = {
    "test-adc.ld": ["header_lines_in_full", "sections_of_the_dialect"],
    "test-i2c-1.ld": ["sections_of_the_dialect"],
    "test-i2c-2.ld": ["sections_of_the_dialect"],
    "test-i2c-lcd16x2.ld": ["sections_of_the_dialect"],
    "test-pwm.ld": ["header_lines_in_full", "sections_of_the_dialect"],
    "test-spi.ld": ["sections_of_the_dialect"],
    "test-uart.ld": ["sections_of_the_dialect", "element_lines_in_long_form", "formatted_strings_as_text"],
    "swatch2.ld": ["header_lines_in_full", "sections_of_the_dialect", "var_list_lines_in_full",
                   "element_lines_in_long_form"],
    "catalog.ld": ["header_lines_in_full", "sections_of_the_dialect", "io_list_as_ldmicro_writes_it",
                   "rungs_numbered_two_blanks_a_level"],
    "demo.ld": ["pullup_lines_end_in_a_blank", "io_list_as_ldmicro_writes_it"],
    "longnames.ld": ["sections_of_the_dialect", "io_list_as_ldmicro_writes_it"],
}


def test_what_keeps_each_5x_corpus_file_from_coming_back_as_stored():
    found: dict[str, list[str]] = {}
    for path in FORMAT_5X:
        assert through_the_text_form(path.read_bytes()) != path.read_bytes().replace(b"\n", b"\r\n")
        rules = in_54_form(path)[1]
        assert found.setdefault(re.sub(r"^(Tests|sample)_", "", path.name), rules) == rules
    assert found == NOT_IN_54_FORM


def test_a_var_list_note_shows_in_the_text_form_and_comes_back():
    """LDmicro 5.4 notes a variable its last compile did not allocate; its
    text export shows the note, and so does ours."""
    path = CORPUS / "ldmicro" / "Tests" / "test-spi.ld"
    ld = load_bytes(path.read_bytes(), "x.ld")
    assert "    2 bytes Cnew \tNow not used !!!" in render_program(ld.program).splitlines()
    assert b"    2 bytes Cnew \tNow not used !!!\r\n" in through_the_text_form(path.read_bytes())
