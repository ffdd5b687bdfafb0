"""DETAILS lines name the rung they belong to by its drawn number
(`SPI SPI in rung 12: ...`), so a rung added, removed or edited elsewhere
never gives an element another element's details; the older `#n` form
(the n-th of the program) is still read. The corpus program test-spi has
SPI elements on one bus with two sets of details, alternating."""

from __future__ import annotations

import random
import re
import sys
from pathlib import Path

import pytest
from test_lsp_incremental import EDIT_CHARS, apply, fresh, snapshot

from lang import codes
from lang.diagnostics import ERROR
from lang.textform.formatter import format_text
from lang.textform.reader import TextReader, read_text

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from lsp_bench import middle_name  # noqa: E402
from shapes import converted, corpus_root  # noqa: E402

TEST_SPI = corpus_root() / "ldmicro" / "Tests" / "test-spi.ld"  # LDmicro0.2, SPI details alternate
BIG = 600  # rungs: enough for a change to reach hundreds of DETAILS lines in the older form
NUMBERED = re.compile(r"^(\d{4})\|", re.MULTILINE)


@pytest.fixture(scope="module")
def text() -> str:
    return converted(TEST_SPI, 12)


def spi_details(program) -> list[list[tuple[str, str, object]]]:
    """Each rung's SPI elements as a user checks them: what is sent and
    received, and the parameters the drawing does not show."""
    return [[(e.args["send"], e.args["recv"], (e.args["modes"], e.args["first"], e.args["bitrate"]))
             for e in rung.elements() if e.kind == "SPI"] for rung in program.rungs]


def clean(text: str):
    program, problems = read_text(text)
    assert not [p for p in problems if p.severity == ERROR], problems
    return program


def rung_lines(text: str, number: int) -> tuple[int, int]:
    """The lines [first, end) of a numbered rung, from the blank line above its names."""
    lines = text.splitlines(keepends=True)
    at = next(i for i, line in enumerate(lines) if line.startswith(f"{number:04d}|"))
    end = next(i for i, line in enumerate(lines) if line.startswith(f"{number + 1:04d}|"))
    return at - 2, end - 2


def test_the_converter_names_the_rung_of_each_differing_detail(text):
    details = text[text.index("\nDETAILS:\n"):].splitlines()[2:]
    assert "  SPI SPI in rung 2: modes 0b11, first MSB_FIRST, bitrate 100000" in details
    assert "  SPI SPI in rung 3: bitrate 100000" in details
    assert not [line for line in details if "#" in line]
    program = clean(text)
    assert spi_details(program)[1] == [("send", "recv0", ("0b11", "MSB_FIRST", "100000"))]
    assert spi_details(program)[2] == [("send", "recv0", ("0", "MSB", "100000"))]


def test_the_older_form_names_the_nth_of_the_program(text):
    """Files written by earlier versions say `SPI SPI #n`: the n-th SPI on
    bus SPI in program order; they read as the new form does."""
    head, details = text.split("\nDETAILS:\n")
    rungs = [int(m) for m in re.findall(r"^  SPI SPI in rung (\d+):", details, re.MULTILINE)]
    older = re.sub(r"^  SPI SPI in rung (\d+):", lambda m: f"  SPI SPI #{rungs.index(int(m.group(1))) + 1}:",
                   details, flags=re.MULTILINE)
    assert "  SPI SPI #2: bitrate 100000" in older
    assert spi_details(clean(head + "\nDETAILS:\n" + older)) == spi_details(clean(text))


def test_a_comment_is_named_by_its_rung():
    program = clean("LADDER DIAGRAM:\n"
                    "0001|| ; first  ||\n\n"
                    "0002|| ; second ||\n\n"
                    "DETAILS:\n  COMMENT in rung 2: line_ends 3\n")
    assert [rung.circuit.items[0].args.get("line_ends") for rung in program.rungs] == [(), ("3",)]


def test_a_rung_inserted_above_keeps_every_elements_details(text):
    """A new rung drawn without a number, or a copy of a rung with its number,
    above the others: no element takes another's details. A copy drawn with
    its original's number has the original's details too (as a copy and
    paste in LDmicro gives)."""
    before = spi_details(clean(text))
    lines = text.splitlines(keepends=True)
    first, end = rung_lines(text, 3)
    copy = lines[first:end]
    unnumbered = ["\n"] + [NUMBERED.sub("    |", line) for line in copy]  # after an empty line
    edited = lines[:first] + copy + unnumbered + lines[first:]  # above rung 3: a copy of it, a new one
    after = spi_details(clean("".join(edited)))
    assert after[:2] + after[4:] == before[:2] + before[2:]
    assert after[2] == before[2]  # the copy, numbered 3 too
    assert after[3] == [("send", "recv0", ("0", "MSB", "1000000"))]  # the unnumbered one: LDmicro's defaults


def test_a_rung_removed_above_changes_no_other_elements_details(text):
    before = spi_details(clean(text))
    lines = text.splitlines(keepends=True)
    first, end = rung_lines(text, 2)
    program, problems = read_text("".join(lines[:first] + lines[end:]))
    # the line naming the removed rung names nothing now: an error at that line
    [problem] = [p for p in problems if p.severity == ERROR]
    assert problem.code == codes.SECTION and "no element of the diagram matches" in problem.message
    assert "SPI SPI in rung 2:" in (lines[:first] + lines[end:])[problem.span.line]
    assert spi_details(program) == before[:1] + before[2:]


def test_the_formatter_renumbers_the_rungs_and_the_details_naming_them(text):
    """Rungs drawn numbered 10, 20, 30... with DETAILS naming them so: the
    formatter numbers them 1, 2, 3... and rewrites the DETAILS lines to
    match: the canonical text again."""
    renumbered = NUMBERED.sub(lambda m: f"{int(m.group(1)) * 10:04d}|", text)
    renumbered = re.sub(r" in rung (\d+):", lambda m: f" in rung {int(m.group(1)) * 10}:", renumbered)
    assert "0120||" in renumbered and "SPI SPI in rung 20:" in renumbered
    assert spi_details(clean(renumbered)) == spi_details(clean(text))
    formatted, _ = format_text(renumbered)
    assert formatted == text


def test_the_formatter_gives_an_inserted_rung_its_own_number_and_keeps_the_details(text):
    lines = text.splitlines(keepends=True)
    first, end = rung_lines(text, 3)
    edited = "".join(lines[:first] + lines[first:end] + lines[first:])
    formatted, _ = format_text(edited)
    assert formatted is not None and "SPI SPI in rung 3: bitrate 100000" in formatted
    assert "SPI SPI in rung 4: bitrate 100000" in formatted
    assert spi_details(clean(formatted)) == spi_details(clean(edited))


def test_an_editor_action_redraws_a_rung_with_the_number_it_has(text):
    """Renaming through the editor draws the rungs again: each keeps its
    drawn number (here 10, 20, ...), so the DETAILS lines naming it still do."""
    from ide.edits import rename
    from ide.locate import Locator

    renumbered = NUMBERED.sub(lambda m: f"{int(m.group(1)) * 10:04d}|", text)
    renumbered = re.sub(r" in rung (\d+):", lambda m: f" in rung {int(m.group(1)) * 10}:", renumbered)
    program = clean(renumbered)
    lines = renumbered.splitlines()
    line_edits, text_edits = rename(program, Locator(program, lines), renumbered, "recv0", "answer")
    assert line_edits and not text_edits
    for edit in sorted(line_edits, key=lambda edit: edit.first, reverse=True):
        lines[edit.first:edit.last] = edit.lines
    renamed = clean("\n".join(lines) + "\n")
    assert any(line.startswith("0020||{->answer send->}") for line in lines)
    assert spi_details(renamed) == [[("send", "answer" if recv == "recv0" else recv, details)
                                     for _, recv, details in rung] for rung in spi_details(program)]


def test_a_rung_after_an_empty_rung_is_drawn_again_with_its_own_number():
    """LDmicro draws an empty rung's number on the next rung's name line."""
    from ide.edits import drawn_number
    from ide.locate import Locator

    text = ("LADDER DIAGRAM:\n"
            "    ||                  ||\n"
            "0001||     Xa       Yb  ||\n"
            "0002||----] [------( )--||\n"
            "    ||                  ||\n"
            "   2||------[END]-------||\n")
    program = clean(text)
    assert len(program.rungs) == 2 and not program.rungs[0].circuit.items
    assert drawn_number(Locator(program, text.splitlines()), 1) == 2


@pytest.mark.parametrize("detail", ["SPI SPI in rung 1: bitrate 5", "SPI SPI in rung 99: bitrate 5",
                                    "SPI SPI in rung 2 #2: bitrate 5", "SPI SPI #99: bitrate 5"])
def test_a_detail_naming_no_element_is_an_error_at_its_line(text, detail):
    edited = text.replace("\nDETAILS:\n", f"\nDETAILS:\n  {detail}\n")
    _, problems = read_text(edited)
    [problem] = [p for p in problems if p.severity == ERROR]
    assert problem.code == codes.SECTION and problem.message == "no element of the diagram matches this detail"
    assert edited.splitlines()[problem.span.line] == f"  {detail}"


@pytest.fixture(scope="module")
def big() -> str:
    return converted(TEST_SPI, BIG)


def read_twice(first: str, second: str):
    """Both versions read by one reader, as the editor does, and how many
    rungs got their details afresh and DETAILS lines were looked up for the
    second."""
    reader = TextReader()
    before, _ = reader.read(first)
    copied, looked_up = reader.details_copied, reader.details_looked_up
    after, problems = reader.read(second)
    assert snapshot((after, problems)) == snapshot(fresh(second))
    return before, after, reader.details_copied - copied, reader.details_looked_up - looked_up


def test_an_edit_of_one_rung_looks_up_the_lines_naming_it_alone(big):
    """test-spi repeated to BIG rungs, a one-character edit of a name in
    the middle: one rung's details set again, and only the DETAILS lines
    naming that rung looked up (with `#n` every later line named another
    element)."""
    lines = big.splitlines()
    line, column = middle_name(lines, BIG)
    lines[line] = lines[line][:column] + "x" + lines[line][column + 1:]
    before, after, copied, looked_up = read_twice(big, "\n".join(lines) + "\n")
    assert copied <= 1 and looked_up <= 1
    assert sum(a is not b for a, b in zip(before.rungs, after.rungs)) == 1


def test_a_rung_repeated_in_the_middle_sets_no_other_rungs_details_again(big):
    """Rungs added move the rungs below to other indexes, not their details:
    no other DETAILS line is looked up again, no other rung detailed again."""
    lines = big.splitlines(keepends=True)
    first, end = rung_lines(big, BIG // 2)
    before, after, copied, looked_up = read_twice(big, "".join(lines[:first] + lines[first:end] + lines[first:]))
    assert copied <= 2  # the rungs the reader read again around the new lines: the copy and its neighbour
    # the lines naming the rungs read again: by their number, or (`SPI_WR SPI:`) by instruction and name alone
    assert looked_up <= 3
    assert spi_details(after) == spi_details(before)[:BIG // 2] + spi_details(before)[BIG // 2 - 1:]


def renumber(text: str, rng: random.Random) -> str:
    """One rung drawn with another number (often one that another rung has), or
    one DETAILS line naming another rung."""
    if rng.random() < 0.5:
        found = list(NUMBERED.finditer(text))
        at = rng.choice(found)
        return text[:at.start()] + f"{rng.randrange(1, 16):04d}|" + text[at.end():]
    found = list(re.finditer(r" in rung (\d+)", text))
    at = rng.choice(found)
    return text[:at.start()] + f" in rung {rng.randrange(1, 16)}" + text[at.end():]


def test_random_edits_of_rungs_and_their_numbers_read_as_a_fresh_reader_does():
    rng = random.Random(12)
    start = converted(TEST_SPI, 15)
    for _ in range(30):
        text, reader = start, TextReader()
        reader.read(text)
        for _ in range(6):
            if rng.random() < 0.4:
                text = renumber(text, rng)
            else:
                text = apply(text, (rng.choice(["type", "delete", "line-dup", "line-del", "replace"]),
                                    rng.randrange(10**6), rng.randrange(10**6), rng.choice(EDIT_CHARS)))
            assert snapshot(reader.read(text)) == snapshot(fresh(text))


def _renamed(text: str, old: str, new: str) -> str:
    """The text after the editor's rename of `old` to `new`, its edits applied."""
    from ide.edits import rename
    from ide.locate import Locator

    program = clean(text)
    lines = text.splitlines()
    line_edits, text_edits = rename(program, Locator(program, lines), text, old, new)
    for edit in sorted(text_edits, key=lambda edit: (edit.line, edit.col), reverse=True):
        lines[edit.line] = lines[edit.line][:edit.col] + edit.text + lines[edit.line][edit.end_col:]
    for line_edit in sorted(line_edits, key=lambda edit: edit.first, reverse=True):
        lines[line_edit.first:line_edit.last] = line_edit.lines
    return "\n".join(lines) + "\n"


TWO_TABLES = """\
LADDER DIAGRAM:
    ||                                  ||
    ||       Xa        {rung        :=} ||
0001||-------] [-------{LUT   tab  [i]}-||
    ||                                  ||
    ||                                  ||
    ||       Xb        {rung        :=} ||
0002||-------] [-------{LUT   tab  [i]}-||
    ||                                  ||
    ||                                  ||
    ||       Xa        {MOV        i:=} ||
0003||-------] [-------{             1}-||
    ||                                  ||
    ||                                  ||
    ||------[END]-----------------------||

DETAILS:
  LOOK_UP_TABLE rung in rung 1: values 10 20 30
  LOOK_UP_TABLE rung in rung 2: values 5 6
"""


def test_a_rename_changes_only_the_name_a_details_line_gives():
    """Two tables written to a variable called `rung`, renamed: the words of
    `in rung N` are not that name, and each table keeps its values."""
    renamed = _renamed(TWO_TABLES, "rung", "level")
    assert renamed.splitlines()[-2:] == ["  LOOK_UP_TABLE level in rung 1: values 10 20 30",
                                         "  LOOK_UP_TABLE level in rung 2: values 5 6"]
    tables = [(e.args["dest"], e.args["values"]) for rung in clean(renamed).rungs for e in rung.elements()
              if e.kind == "LOOK_UP_TABLE"]
    assert tables == [("level", ("10", "20", "30")), ("level", ("5", "6"))]


def test_a_rung_inserted_by_the_editor_takes_no_other_rungs_details():
    """A copy of rung 2 inserted above it is drawn with a number no rung has,
    so `in rung 2` still names only rung 2's table."""
    from ide.edits import insert_rung
    from ide.locate import Locator

    program = clean(TWO_TABLES)
    lines = TWO_TABLES.splitlines()
    copied = program.rungs[1]
    edit = insert_rung(Locator(program, lines), TWO_TABLES, 1, copied)
    lines[edit.first:edit.last] = edit.lines
    tables = [e.args["values"] for rung in clean("\n".join(lines) + "\n").rungs for e in rung.elements()
              if e.kind == "LOOK_UP_TABLE"]
    assert tables == [("10", "20", "30"), (), ("5", "6")]
