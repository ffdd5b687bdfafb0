"""The text form against LDmicro's own exports: every export reads, its model
equals the model of the .ld it came from (except what the export does not
carry), and our drawing of a program is LDmicro's, line for line."""

from __future__ import annotations

import pytest
from corpus import export_pairs

from lang.diagnostics import ERROR
from lang.loader import load_path
from lang.textform.formatter import existing_width, format_text
from lang.textform.reader import read_text, rung_blocks
from lang.textform.sections import DIAGRAM, split_sections
from lang.textform.writer import render_program, render_rung

PAIRS = export_pairs()
IDS = [txt.stem for txt, _ in PAIRS]

# Rungs (1-based) where LDmicro cut something when exporting: a name or a
# comment line ending in `~`, a formatted string shown only to 27 characters,
# an I2C box whose fields LDmicro ran together. Their models cannot match.
TRUNCATED = {
    "Tests_test-adc": {1}, "Tests_test-i2c-lcd16x2": {4}, "Tests_test-leds": {1}, "Tests_test-pwm": {1},
    "Tests_test-uart": {1, 4}, "catalog": {66}, "reg_tests_avr-hw": {1}, "reg_tests_contacts": {1},
    "reg_tests_integers": {1}, "reg_tests_misc-ops": {1}, "reg_tests_pic16-hw": {1},
    "reg_tests_timers-counters": {1}, "sample_7seg-display": {1, 7}, "sample_coil_s_r_n": {1},
    "sample_frmt_escape": {3, 5}, "sample_hello": {1, 3}, "sample_pic-adc": {12}, "sample_swatch1": {3, 5, 12},
    "sample_swatch2": {6, 7, 12}, "sample_var-timer": {1, 9},
}
# Rungs LDmicro drew over their own borders (a name or glyph longer than its
# cell overwrote the neighbour): they are reported as located errors.
DAMAGED = {"longnames": {1, 2}, "sample_ctu_ctd_ctc_ctr": {6}}
# Rungs that are cut nowhere, yet drawn differently: an 18-character coil name
# that LDmicro let run over the right rail, where we widen the cell.
OVERFLOWING = {"sample_swatch1": {5, 8, 12}, "sample_swatch2": {7, 12}}

# What an export never carries (ldmicro-formats.md §1.12), reset before comparing:
# - every field the drawing does not show (timer adjust, LUT values, PWL points,
#   UART byte counts, SPI/I2C details, SET PWM resolution, SLEEP values, BUS map),
# - the settings after the header line (baud, SPI/I2C rates, cycle timer,
#   cycle duty output, configuration word, COMPILED, COMPILER, the .ld dialect),
# - VAR LIST, which is LDmicro session state in both files,
# - trailing blanks at the end of a comment line (LDmicro drops them on export).


def _comparable(program):
    for _, element in program.elements():
        for f in element.spec.fields:
            if not f.drawn:
                element.args[f.name] = f.default
        if element.kind == "COMMENT":
            element.args["text"] = "\n".join(line.rstrip() for line in element.args["text"].split("\n"))
    return program


def _diagram_lines(path):
    lines = path.read_text(encoding="cp1252").splitlines()
    start = lines.index("LADDER DIAGRAM:") + 1
    end = start
    while end < len(lines) and lines[end].strip():
        end += 1
    return lines, lines[start:end]


def _export_rungs(text: str):
    """The export's lines of each rung, by rung number."""
    section = next(s for s in split_sections(text.splitlines()) if s.title == DIAGRAM)
    blocks = rung_blocks(section, [])
    return {number: [line.text for line in block] for number, (block, _) in enumerate(blocks, 1)}


@pytest.mark.parametrize(("txt", "ld"), PAIRS, ids=IDS)
def test_export_reads_to_the_model_of_its_ld(txt, ld):
    exported, problems = load_path(txt)
    original, ld_problems = load_path(ld)
    assert not [p for p in ld_problems if p.severity == ERROR]
    damaged = DAMAGED.get(txt.stem, set())
    errors = [p for p in problems if p.severity == ERROR]
    if not damaged:
        assert not errors, [p.format(txt.name) for p in errors]
    else:
        assert errors, "LDmicro damaged this export; the damage must be reported"
    _comparable(exported)
    _comparable(original)
    assert exported.settings.mcu == original.settings.mcu
    assert exported.settings.crystal_hz == original.settings.crystal_hz
    assert exported.settings.cycle_us == original.settings.cycle_us
    assert exported.pins == {k: v for k, v in original.pins.items() if k in exported.pins}
    cut = TRUNCATED.get(txt.stem, set())
    first_damaged = min(damaged, default=len(original.rungs) + 1)
    for number, (mine, theirs) in enumerate(zip(exported.rungs, original.rungs), 1):
        if number >= first_damaged:
            break
        if number in cut:
            assert mine != theirs, f"rung {number} is listed as truncated but matches: update TRUNCATED"
        else:
            assert mine == theirs, f"rung {number} differs"


@pytest.mark.parametrize(("txt", "ld"), PAIRS, ids=IDS)
def test_formatting_an_export_keeps_its_diagram(txt, ld):
    text = txt.read_text(encoding="cp1252")
    if txt.stem in DAMAGED:
        assert format_text(text)[0] is None, "a file with errors must not be rewritten"
        return
    formatted, _ = format_text(text)
    _, before = _diagram_lines(txt)
    after = formatted.splitlines()
    after = after[after.index("LADDER DIAGRAM:") + 1:]
    after = after[:after.index("")]
    skip = TRUNCATED.get(txt.stem, set()) | OVERFLOWING.get(txt.stem, set())
    if not skip:
        assert after == before
        return
    theirs, ours = _export_rungs(text), _export_rungs(formatted)
    assert len(theirs) == len(ours)
    for number in theirs:
        if number not in skip:
            assert ours[number] == theirs[number], f"rung {number}"


@pytest.mark.parametrize(("txt", "ld"), PAIRS, ids=IDS)
def test_converting_the_ld_draws_the_export(txt, ld):
    """Rung by rung wherever LDmicro cut nothing. The diagram width is the
    export's: LDmicro widens it for long comments up to its window's width."""
    text = txt.read_text(encoding="cp1252")
    program, _ = load_path(ld)
    columns = existing_width(text)
    theirs = _export_rungs(text)
    skip = TRUNCATED.get(txt.stem, set()) | OVERFLOWING.get(txt.stem, set()) | DAMAGED.get(txt.stem, set())
    compared = 0
    for number, rung in enumerate(program.rungs, 1):
        if number in skip or not rung.circuit.items:
            continue
        drawn = render_rung(rung, number, columns)
        expected = list(theirs[number])
        if number > 1 and not program.rungs[number - 2].circuit.items:
            # an empty rung's number sits on the next rung's first line
            expected[0] = "    " + expected[0][4:]
        assert drawn[:len(expected)] == expected, f"rung {number}"
        compared += 1
    assert compared or txt.stem in DAMAGED


def test_an_untruncated_export_is_drawn_whole_from_its_ld():
    for txt, ld in PAIRS:
        if txt.stem in TRUNCATED or txt.stem in DAMAGED or txt.stem in OVERFLOWING:
            continue
        program, _ = load_path(ld)
        _, before = _diagram_lines(txt)
        drawn = render_program(program, existing_width(txt.read_text(encoding="cp1252"))).splitlines()
        drawn = drawn[drawn.index("LADDER DIAGRAM:") + 1:]
        assert drawn[:drawn.index("")] == before, txt.name


@pytest.mark.parametrize(("txt", "ld"), PAIRS, ids=IDS)
def test_fmt_is_idempotent_and_keeps_the_model(txt, ld):
    text = txt.read_text(encoding="cp1252")
    once, _ = format_text(text)
    if once is None:
        return
    twice, _ = format_text(once)
    assert twice == once
    assert read_text(once)[0] == read_text(text)[0]


@pytest.mark.parametrize("ld", [p for p in __import__("corpus").all_ld_files()], ids=lambda p: p.parent.name + "/" + p.name)
def test_every_ld_survives_the_text_form(ld):
    """.ld -> .ladder -> .ld loses nothing: settings, pins, sizes, every
    element parameter (what the drawing does not show goes to DETAILS)."""
    from lang.ldfile import read_ld, write_ld

    original, _ = load_path(ld)
    text = render_program(original)
    through_text, problems = read_text(text)
    assert not [p for p in problems if p.severity == ERROR], [p.format("x") for p in problems]
    assert through_text == original
    assert read_ld(write_ld(through_text))[0] == original
