"""DETAILS attached to the rungs they name as a document is edited: a
converted LDmicro 0.1 program (a DETAILS line per timer), 2,000 rungs, where
an edit must give each rung its details again only where it changed."""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest
from test_lsp_incremental import EDIT_CHARS, apply, fresh, snapshot

from lang.textform.reader import TextReader

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from lsp_bench import middle_name  # noqa: E402
from shapes import converted, corpus_root  # noqa: E402

RUNGS = 2000
TIMERS_COUNTERS = corpus_root() / "ldmicro" / "reg" / "tests" / "timers-counters.ld"  # LDmicro0.1, with timers


@pytest.fixture(scope="module")
def text() -> str:
    return converted(TIMERS_COUNTERS, RUNGS)


def read_twice(first: str, second: str):
    reader = TextReader()
    before, _ = reader.read(first)
    copied = reader.details_copied
    after, problems = reader.read(second)
    assert snapshot((after, problems)) == snapshot(fresh(second))
    return before, after, reader.details_copied - copied, reader


def test_the_shape_has_details_for_its_timers(text):
    details = text[text.index("\nDETAILS:"):].splitlines()[2:]
    assert len(details) > RUNGS / 4 and all(": adjust -1" in line for line in details)


def test_a_one_character_edit_gives_one_rung_its_details_again(text):
    lines = text.splitlines()
    line, column = middle_name(lines, RUNGS)
    lines[line] = lines[line][:column] + "x" + lines[line][column + 1:]
    before, after, copied, _ = read_twice(text, "\n".join(lines) + "\n")
    assert copied <= 1
    assert sum(a is not b for a, b in zip(before.rungs, after.rungs)) == 1


def test_a_line_added_moves_the_detailed_rungs_below_without_copying_them(text):
    lines = text.splitlines()
    line, _ = middle_name(lines, RUNGS)
    lines.insert(line, lines[line - 1])  # the blank wire line above the names, once more
    before, after, copied, reader = read_twice(text, "\n".join(lines) + "\n")
    assert copied <= 1  # the rung the line went into
    moved = [rung for rung in after.rungs if id(rung) in reader.moved]
    assert len(moved) > RUNGS / 4
    assert all(reader.moved[id(rung)][0] in before.rungs and reader.moved[id(rung)][1] == 1 for rung in moved)


def test_a_changed_detail_gives_only_its_rung_its_details_again(text):
    at = text.index(": adjust -1", text.index("\nDETAILS:"))
    before, after, copied, _ = read_twice(text, text[:at] + ": adjust 3" + text[at + len(": adjust -1"):])
    assert copied == 1
    changed = [index for index, (a, b) in enumerate(zip(before.rungs, after.rungs)) if a is not b]
    assert len(changed) == 1
    assert 3 in [e.args.get("adjust") for e in after.rungs[changed[0]].elements()]


def test_random_edits_read_as_a_fresh_reader_does():
    rng = random.Random(21)
    start = converted(TIMERS_COUNTERS, 40)
    for _ in range(30):
        text, reader = start, TextReader()
        for _ in range(6):
            text = apply(text, (rng.choice(["type", "delete", "line-dup", "line-del", "replace"]),
                                rng.randrange(10**6), rng.randrange(10**6), rng.choice(EDIT_CHARS)))
            assert snapshot(reader.read(text)) == snapshot(fresh(text))


def test_a_rung_removed_and_another_repeated_moves_the_details_with_their_rungs(text):
    lines = text.splitlines(keepends=True)
    numbered = [i for i, line in enumerate(lines) if line[:4].isdigit() and line[4] == "|"]
    rung = lines[numbered[10] - 2:numbered[11] - 2]  # a rung, from the blank line above its names
    edited = lines[:numbered[10] - 2] + lines[numbered[11] - 2:numbered[20] - 2] + rung + lines[numbered[20] - 2:]
    read_twice(text, "".join(edited))
