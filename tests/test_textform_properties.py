"""Round trips on random valid programs: drawing and reading back gives the
same program, formatting is idempotent, and .ld -> .ladder -> .ld loses nothing."""

from __future__ import annotations

import pytest
from generators import DRAWABLE, element_of, programs
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from lang.diagnostics import ERROR
from lang.ldfile import read_ld, write_ld
from lang.model import Element, Parallel, Program, Rung, Series, rung_circuit
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


@pytest.mark.parametrize("instruction", DRAWABLE, ids=lambda i: i.key)
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_every_field_of_every_element_survives_ldmicros_own_drawing(instruction, data):
    """An element as LDmicro's export draws it (no DETAILS: the values the
    drawing lacks take LDmicro's defaults) goes to .ld and back unchanged,
    every field in its place."""
    element = data.draw(element_of(instruction))
    rung = [element] if instruction.eol else [element, Element("COIL", {"name": "Yout", "type": " "})]
    text = render_program(Program(rungs=[Rung(rung_circuit(Series(rung)))]))
    drawing_only = text.split("\nDETAILS:", 1)[0]
    program, problems = read_text(drawing_only)
    assume(not _errors(problems))
    written = write_ld(program)
    again, problems = read_ld(written)
    assert not _errors(problems), (written, problems)
    assert [(e.kind, e.args) for _, e in again.elements()] == [(e.kind, e.args) for _, e in program.elements()]
    drawn = {f.name for f in instruction.fields if f.drawn}
    read = next(e for _, e in program.elements() if e.kind == instruction.key)
    assert {k: v for k, v in read.args.items() if k in drawn} == \
        {k: v for k, v in element.args.items() if k in drawn}


def test_a_program_of_more_than_9999_rungs_reads_back():
    """Rung numbers of five digits widen the margin of every line, so each
    rung's rail stays in one column (LDmicro never writes them: it loads 9,999)."""
    from builders import coil, contact, el

    def branched(n):
        return Rung(Series([Parallel([contact(f"X{n}"), contact(f"Y{n}", negated=1)]), coil(f"Y{n}")]))

    rungs = [branched(n) for n in range(10_003)]
    rungs[9_998] = Rung(Series([]))  # an empty rung shows its number on the next line
    rungs[10_001] = Rung(Series([el("COMMENT", text="after\nten thousand")]))
    program = Program(rungs=rungs)
    text = render_program(program)
    read, problems = read_text(text)
    assert not _errors(problems), problems[:3]
    assert read == program
    assert format_text(text)[0] == text
