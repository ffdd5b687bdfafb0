"""docs/elements.md is generated from the instruction table, every example
on it reads back as its instruction, and LD003 names the closest drawings."""

from __future__ import annotations

from pathlib import Path

import pytest

from lang.instructions import INSTRUCTIONS
from lang.reference import example_program, examples, render
from lang.textform.reader import read_text
from lang.textform.writer import render_program

DOC = Path(__file__).resolve().parents[1] / "docs" / "elements.md"


def test_the_page_is_current():
    assert DOC.read_text(encoding="utf-8") == render(), \
        "docs/elements.md is stale: python -m lang.reference > docs/elements.md"


@pytest.mark.parametrize("key", sorted(examples()))
def test_every_example_reads_back_as_its_instruction(key):
    text = render_program(example_program(key))
    program, problems = read_text(text)
    assert [p for p in problems if p.severity == "error"] == []
    assert key in {element.kind for _, element in program.elements()}
    assert key in DOC.read_text(encoding="utf-8")


def test_every_drawn_instruction_is_on_the_page():
    assert set(examples()) == set(INSTRUCTIONS) - {"PLACEHOLDER"}


def test_the_examples_read_in_one_parse_are_those_read_one_by_one():
    from lang.reference import _example

    assert {key: (e.kind, e.args) for key, e in examples().items()} == \
        {key: (_example(key).kind, _example(key).args) for key in examples()}


def test_an_example_line_that_does_not_read_is_named(monkeypatch):
    from dataclasses import replace

    import lang.reference as reference

    broken = replace(INSTRUCTIONS["MOVE"], example="MOVE onlyone")
    monkeypatch.setitem(reference.INSTRUCTIONS, "MOVE", broken)
    with pytest.raises(ValueError, match="the example line of MOVE does not read"):
        reference.examples.__wrapped__()


@pytest.mark.parametrize("typed, expected", [
    ("[CTU >=5]", "did you mean `/[CTU>=10]` (up counter)"),
    ("{CTC 0:7}", "did you mean `/[CTC  0:9]` (circular counter)"),
    ("{PWM 32.8 kHz}", "did you mean `{PWM  PWMoutpin}` (set PWM duty cycle)"),
    ("[TOFF 1 s]", "`[TOF 100 ms]` (turn-off delay)"),
])
def test_an_unknown_drawing_gets_the_closest_forms(typed, expected):
    text = f"LDmicro export text.\n\nLADDER DIAGRAM:\n    ||        Ya     ||\n0001||-----{typed}---( )-----||\n"
    problems = read_text(text)[1]
    assert any(p.code == "LD003" and expected in p.message for p in problems), [p.message for p in problems]


@pytest.mark.parametrize("glyph, what", [("] [", "contact"), ("]/[", "contact"), ("( )", "coil"), ("(S)", "coil")])
def test_a_contact_or_coil_without_a_name_says_so(glyph, what):
    text = f"LDmicro export text.\n\nLADDER DIAGRAM:\n    ||                        ||\n0001||-----{glyph}---------||\n"
    messages = [p.message for p in read_text(text)[1] if p.code == "LD003"]
    assert messages == [f"this {what} has no name: write it on the line above '{glyph}'"]
