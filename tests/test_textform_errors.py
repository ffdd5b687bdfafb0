"""Damaged drawings give located errors, never a traceback."""

from __future__ import annotations

import random

import pytest
from corpus import EXPORTS
from hypothesis import given
from hypothesis import strategies as st
from mutations import mutate

from ide.fixes import fix_all
from lang import codes
from lang.loader import load_bytes
from lang.textform.formatter import format_text
from lang.textform.reader import read_text

GOOD = """LADDER DIAGRAM:
    ||                                                   ||
    ||     Xstart            Xstop             Rrun       ||
0001|+-------] [------+-------]/[----------------( )-------||
    ||                |                                   ||
    ||      Rrun      |                                   ||
    |+-------] [------+                                   ||
    ||                                                   ||
"""


def _problems(text: str):
    program, problems = read_text(text)
    return problems


def _one(text: str, code: str):
    found = [p for p in _problems(text) if p.code == code]
    assert found, _problems(text)
    return found[0]


def test_the_good_rung_reads():
    assert _problems(GOOD) == []


def test_a_missing_wire_is_located():
    broken = GOOD.replace("+-------]/[----------------( )", "+-------]/[----     -------( )")
    problem = _one(broken, codes.BROKEN_WIRE)
    assert (problem.span.line, problem.span.col) == (3, 37)


# a connector glyph a column off: one error, at the glyph, naming its column
# and the `+` it lines up with; the rung read as if it were there
MISPLACED = [
    ("the branch's closing `+` one column right",
     "    |+-------] [------+  ", "    |+-------] [-------+ ",
     "7:24: error LD014 move '+' to column 23, under the '+' of line 4"),
    ("the branch's closing `+` one column left",
     "    |+-------] [------+  ", "    |+-------] [-----+   ",
     "7:22: error LD014 move '+' to column 23, under the '+' of line 4"),
    ("the branch's `|` one column right",
     "    ||      Rrun      |  ", "    ||      Rrun       | ",
     "6:24: error LD014 move '|' to column 23, under the '+' of line 4"),
    ("the `|` below the junction one column left",
     "    ||                |          ", "    ||               |           ",
     "5:22: error LD014 move '|' to column 23, under the '+' of line 4"),
    ("the junction on the wire one column right",
     "[------+-------]/[", "[-------+------]/[",
     "4:24: error LD014 move '+' to column 23, above the '+' of line 7"),
]


@pytest.mark.parametrize("case", MISPLACED, ids=[case[0] for case in MISPLACED])
def test_a_connector_glyph_one_column_off_says_where_it_belongs(case):
    _, old, new, expected = case
    broken = GOOD.replace(old, new, 1)
    assert broken != GOOD
    assert [p.format("f") for p in _problems(broken)] == [f"f:{expected}"]


@pytest.mark.parametrize("case", MISPLACED, ids=[case[0] for case in MISPLACED])
def test_the_fix_moves_the_glyph_back(case):
    _, old, new, _ = case
    fixed, titles = fix_all(GOOD.replace(old, new, 1), "ladder")
    assert fixed == GOOD
    glyph = case[3].split("move '")[1][0]
    assert titles == [f"move '{glyph}' to column 23"]


def test_a_misplaced_glyph_does_not_hide_the_rung_s_other_errors():
    broken = GOOD.replace("    |+-------] [------+  ", "    |+-------] [-------+ ").replace("]/[", "[?]")
    assert sorted(p.format("f") for p in _problems(broken)) == [
        "f:4:31: error LD003 no instruction is drawn like 'Xstop / [?]'",
        "f:7:24: error LD014 move '+' to column 23, under the '+' of line 4",
    ]


def test_a_middle_junction_off_is_one_error():
    three = GOOD.replace("    |+-------] [------+                                   ||\n",
                         "    |+-------] [------+                                   ||\n"
                         "    ||                |                                   ||\n"
                         "    ||      Rrun      |                                   ||\n"
                         "    |+-------] [------+                                   ||\n")
    assert _problems(three) == []
    broken = three.replace("    |+-------] [------+  ", "    |+-------] [-------+ ", 1)
    assert [p.format("f") for p in _problems(broken)] == [
        "f:7:24: error LD014 move '+' to column 23, under the '+' of line 4"]


def test_a_cut_off_box_is_an_unknown_element():
    text = GOOD.replace("( )", "{MO").replace("Rrun       ||", "Rrun       ||", 1)
    problem = _one(text, codes.UNKNOWN_ELEMENT)
    assert problem.span.line == 3


def test_an_unknown_glyph_is_an_unknown_element():
    problem = _one(GOOD.replace("]/[", "[?]"), codes.UNKNOWN_ELEMENT)
    assert problem.span.line == 3 and "[?]" in problem.message


def test_a_name_above_nothing():
    text = GOOD.replace("    ||                |                                   ||",
                        "    ||                |              Stray                ||", 1)
    problem = _one(text, codes.STRAY_TEXT)
    assert problem.span.line == 4 and "Stray" in problem.message


def test_a_bridge_is_not_series_parallel():
    bridge = """LADDER DIAGRAM:
    ||       Xa               Xb              Yc       ||
0001|+-------] [------+-------] [------+-------( )-----||
    ||                |                |               ||
    ||       Xd       |       Xe       |               ||
    |+-------] [------+-------] [------+               ||
    ||                |                                ||
    ||                |       Xf                       ||
    ||                +-------] [-------               ||
"""
    problems = _problems(bridge)
    assert any(p.code in (codes.NOT_SERIES_PARALLEL, codes.BROKEN_WIRE, codes.BAD_JUNCTION) for p in problems)


def test_a_junction_with_nothing_below():
    text = GOOD.replace("|+-------] [------+                                   ||",
                        "|+-------] [-------                                   ||")
    problem = _one(text, codes.BAD_JUNCTION)
    assert problem.span.line in (3, 4, 5, 6)


def test_binary_garbage_is_unreadable_not_a_crash():
    loaded = load_bytes(bytes(range(256)) * 10, "junk.ladder")
    assert [p.code for p in loaded.diagnostics] == [codes.UNREADABLE]


def test_invalid_utf8_is_located():
    loaded = load_bytes(b"LADDER DIAGRAM:\n    ||  \xff\xfe  ||\n", "bad.ladder")
    problem = next(p for p in loaded.diagnostics if p.code == codes.UNREADABLE)
    assert (problem.span.line, problem.span.col) == (1, 8)


def test_a_ten_megabyte_file_gives_errors_not_a_traceback():
    line = "    ||--] [--( )--  garbage {{ [[ ]] ++ || \n"
    text = "LADDER DIAGRAM:\n" + line * (10 * 1024 * 1024 // len(line))
    program, problems = read_text(text)
    assert problems


def test_a_file_with_errors_is_not_reformatted():
    assert format_text(GOOD.replace("]/[", "[?]"))[0] is None


def _mutations():
    texts = [path.read_text(encoding="cp1252") for path in sorted(EXPORTS.glob("*.txt"))]
    return st.tuples(st.sampled_from(texts), st.integers(0, 2**32 - 1), st.integers(1, 8))


@given(_mutations())
def test_mutated_corpus_rungs_never_crash(case):
    text, seed, count = case
    mutated = mutate(text, random.Random(seed), count)
    program, problems = read_text(mutated)
    lines = mutated.count("\n") + 1
    for problem in problems:
        assert problem.span is None or 0 <= problem.span.line < lines
        assert problem.message


def test_details_do_not_stick_to_cached_rungs():
    """The reader caches rungs; a DETAILS line applies to this text only."""
    text = ("LADDER DIAGRAM:\n    ||      Xa             Tdly     ||\n"
            "0001||-------] [-------[TON 1 s]--||\n    ||                          ||\n\n"
            "DETAILS:\n  TON Tdly: adjust -1\n")
    with_detail, _ = read_text(text)
    without, _ = read_text(text[:text.index("DETAILS:")])
    again, _ = read_text(text)
    timer = lambda program: next(e for _, e in program.elements() if e.kind == "TON")  # noqa: E731
    assert (timer(with_detail).args["adjust"], timer(without).args["adjust"], timer(again).args["adjust"]) == (-1, 0, -1)
