"""Elements that differ from one read before in their names alone, as a
converted program repeats them: each reads as it would alone (the reader
takes such an element from the one it knows: lang/textform/renamed.py),
also where a new name is no name, or is the name another operand of the
element stands for."""

from __future__ import annotations

import pytest

from lang.model import Element, Program, Rung, Series, Settings
from lang.textform import renamed, rungs
from lang.textform.elements import complete_args
from lang.textform.reader import read_text
from lang.textform.writer import render_program


def element(kind: str, **args: object) -> Element:
    return Element(kind, complete_args(kind, args))


def program_text(rungs_drawn: list[list[Element]]) -> str:
    return render_program(Program(Settings(mcu="Atmel AVR ATmega328 28-PDIP"),
                                  [Rung(Series(elements)) for elements in rungs_drawn]))


def placed(program: Program) -> list[list[tuple]]:
    return [[(e.kind, e.args, e.span, e.arg_spans) for e in rung.elements()] for rung in program.rungs]


@pytest.fixture
def forgetting(monkeypatch):
    """Reads with nothing known from an earlier read, then reads alone: with
    every element read in full."""
    def forget() -> None:
        monkeypatch.setattr(renamed, "_KNOWN", {})
        monkeypatch.setattr(rungs, "_RECIPES", {})
        rungs._element_plan.cache_clear()

    def read_twice(text: str):
        forget()
        together = read_text(text)
        forget()
        monkeypatch.setattr(rungs, "renamed", lambda *_: None)
        alone = read_text(text)
        return together, alone
    return read_twice


def test_copies_with_other_names_read_to_their_own_names_at_their_own_places(forgetting):
    text = program_text([[element("CONTACTS", name=f"Xin{n}"), element("CTU", name=f"Cup{n}", max="4", init=str(n)),
                          element("MOVE", dest=f"var{n}", src="y")] for n in range(10)])
    (program, problems), (alone, alone_problems) = forgetting(text)
    assert not problems and placed(program) == placed(alone)
    lines = text.splitlines()
    for n, rung in enumerate(program.rungs):
        contact, counter, move = rung.elements()
        assert (contact.args["name"], counter.args["name"], counter.args["init"], move.args["dest"]) == \
            (f"Xin{n}", f"Cup{n}", str(n), f"var{n}")
        for e in (contact, counter, move):
            for name, at in e.arg_spans.items():
                assert lines[at.line][at.col:at.end_col] == str(e.args[name])


def test_a_new_name_that_another_operand_holds_takes_that_operand_s_place_as_alone(forgetting):
    # the source `y` is found in the glyph below, until a copy names its destination `y` too:
    # then the first whole word `y` is the one on top
    text = program_text([[element("MOVE", dest="x", src="y")], [element("MOVE", dest="y", src="y")]])
    (program, problems), (alone, alone_problems) = forgetting(text)
    assert not problems and placed(program) == placed(alone)
    move = next(program.rungs[1].elements())
    assert move.arg_spans["src"] == move.arg_spans["dest"]


def test_a_new_name_that_is_no_name_is_an_error_as_alone(forgetting):
    text = program_text([[element("CONTACTS", name="Xa1")], [element("CONTACTS", name="Xa2")]])
    text = text.replace(" Xa2 ", " 4a2 ")
    (program, problems), (alone, alone_problems) = forgetting(text)
    assert [p.code for p in problems] == ["LD003"] and problems == alone_problems
    assert placed(program) == placed(alone)


def test_a_new_name_drawn_elsewhere_on_top_is_placed_as_alone(forgetting):
    # a destination named as the instruction's own word: its first whole word on top is that word
    text = program_text([[element("MOVE", dest="abc", src="1")], [element("MOVE", dest="MOV", src="1")]])
    (program, problems), (alone, alone_problems) = forgetting(text)
    assert problems == alone_problems and placed(program) == placed(alone)
