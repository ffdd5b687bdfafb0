"""Round trips on random valid programs: drawing and reading back gives the
same program, formatting is idempotent, and .ld -> .ladder -> .ld loses nothing."""

from __future__ import annotations

from generators import programs
from hypothesis import given

from lang.diagnostics import ERROR
from lang.ldfile import read_ld, write_ld
from lang.textform.formatter import format_text
from lang.textform.reader import read_text
from lang.textform.writer import render_program


def _errors(problems):
    return [p for p in problems if p.severity == ERROR]


@given(programs())
def test_drawing_reads_back_as_the_same_program(program):
    text = render_program(program)
    read, problems = read_text(text)
    assert not _errors(problems), (text, problems)
    assert read == program


@given(programs())
def test_fmt_is_idempotent(program):
    text = render_program(program)
    once, _ = format_text(text)
    assert once == text
    assert format_text(once, reflow=True)[0] == format_text(format_text(once, reflow=True)[0])[0]


@given(programs())
def test_ld_to_text_to_ld_is_lossless(program):
    through_ld, problems = read_ld(write_ld(program))
    assert not _errors(problems)
    through_text, problems = read_text(render_program(through_ld))
    assert not _errors(problems)
    assert read_ld(write_ld(through_text))[0] == through_ld
