"""Reading a text again after an edit (lang.textform.reader.TextReader, what
the language server does through ide.incremental) gives exactly what a reader
that never saw the text gives, spans included, after any sequence of edits;
and an edit inside one rung reads only that rung."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from generators import programs
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lsprotocol import types

from ide.incremental import IncrementalReader
from lang.textform.reader import Edited, TextReader
from lang.textform.writer import render_program
from lsp.text import LineDocument

ROOT = Path(__file__).resolve().parents[1]
EXPORTS = sorted((ROOT.parent / "shared" / "corpus" / "ldmicro-export").glob("*.txt"))
EXAMPLE = (ROOT / "examples" / "conveyor.ladder").read_text(encoding="utf-8")


def snapshot(value):
    """Everything in a model value, positions included (model equality ignores them)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return (type(value).__name__,) + tuple(
            (f.name, snapshot(getattr(value, f.name))) for f in dataclasses.fields(value))
    if isinstance(value, dict):
        return tuple(sorted((str(k), snapshot(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return tuple(snapshot(v) for v in value)
    return value


def fresh(text: str):
    return TextReader(cache_size=0).read(text)  # no state, nothing cached


def same(incremental: IncrementalReader, text: str, edited: Edited | None = None) -> None:
    program, problems = incremental.read(text, edited)
    expected_program, expected_problems = fresh(text)
    assert snapshot(problems) == snapshot(expected_problems)
    assert snapshot(program) == snapshot(expected_program)


def corpus_texts() -> list[str]:
    texts = [EXAMPLE]
    for path in EXPORTS[:12]:
        texts.append(path.read_bytes().decode("cp1252", errors="replace"))
    return texts


@pytest.mark.parametrize("number", range(len(corpus_texts())))
def test_full_read_matches_reader(number):
    text = corpus_texts()[number]
    same(IncrementalReader("ladder"), text)


EDIT_CHARS = " -|+[]()/X0123456789;{}\n"


@st.composite
def edits(draw, text: str):
    """A few edits: characters typed or deleted anywhere, lines duplicated or removed."""
    steps = []
    for _ in range(draw(st.integers(1, 6))):
        kind = draw(st.sampled_from(["type", "delete", "line-dup", "line-del", "replace"]))
        steps.append((kind, draw(st.integers(0, 10**6)), draw(st.integers(0, 10**6)),
                      draw(st.sampled_from(EDIT_CHARS))))
    return steps


def apply(text: str, step) -> str:
    kind, a, b, ch = step
    lines = text.splitlines(keepends=True)
    if not lines:
        return ch
    line = a % len(lines)
    if kind == "line-dup":
        return "".join(lines[:line + 1] + [lines[line]] + lines[line + 1:])
    if kind == "line-del":
        return "".join(lines[:line] + lines[line + 1:])
    offset = sum(len(ln) for ln in lines[:line]) + b % max(1, len(lines[line]))
    if kind == "type":
        return text[:offset] + ch + text[offset:]
    if kind == "delete":
        return text[:offset] + text[offset + 1:]
    return text[:offset] + ch + text[offset + 1:]


@settings(max_examples=150, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(data=st.data())
def test_edits_of_the_example(data):
    incremental = IncrementalReader("ladder")
    text = EXAMPLE + "\nDETAILS:\n  TON Twarn: adjust -1\n"
    same(incremental, text)
    for step in data.draw(edits(text)):
        text = apply(text, step)
        same(incremental, text)


@settings(max_examples=60, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large], deadline=None)
@given(program=programs(), data=st.data())
def test_edits_of_generated_programs(program, data):
    text = render_program(program)
    incremental = IncrementalReader("ladder")
    same(incremental, text)
    for step in data.draw(edits(text)):
        text = apply(text, step)
        same(incremental, text)


def change_of(document: LineDocument, step) -> types.TextDocumentContentChangePartial:
    """`apply`'s edit as an editor sends it."""
    kind, a, b, ch = step
    lines = document.lines
    line = a % len(lines) if lines else 0
    col = b % max(1, len(lines[line].rstrip("\r\n"))) if lines else 0
    start, end, text = (line, col), (line, col + 1), ch
    if kind == "line-dup":
        start, end, text = (line, 0), (line, 0), lines[line] if lines else ch
    elif kind == "line-del":
        start, end, text = (line, 0), (line + 1, 0), ""
    elif kind == "type":
        end = start
    elif kind == "delete":
        text = ""
    return types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(*start), end=types.Position(*end)), text=text)


@settings(max_examples=150, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(data=st.data())
def test_edits_the_editor_reports_read_as_a_fresh_reader_does(data):
    """The language server tells the reader which lines no edit touched
    (lsp/text.py); a read may follow several edits."""
    text = EXAMPLE + "\nDETAILS:\n  TON Twarn: adjust -1\n"
    document = LineDocument("file:///t.ladder", text)
    incremental = IncrementalReader("ladder")
    same(incremental, document.source, document.take_edited())
    for step in data.draw(edits(text)):
        document.apply_change(change_of(document, step))
        if data.draw(st.booleans()):
            same(incremental, document.source, document.take_edited())
    same(incremental, document.source, document.take_edited())


def big_text(rungs: int = 200) -> str:
    lines = EXAMPLE.splitlines(keepends=True)
    start = next(i for i, ln in enumerate(lines) if ln.startswith("LADDER DIAGRAM"))
    end = next(i for i, ln in enumerate(lines) if "[END]" in ln)
    body = lines[start + 1:end - 1]
    return "".join(lines[:start + 1] + body * (rungs // 4) + lines[end - 1:])


def test_an_edit_in_one_rung_reads_only_that_rung():
    text = big_text()
    incremental = IncrementalReader("ladder")
    program, _ = incremental.read(text)
    assert incremental.last_mode == "full"
    lines = text.splitlines(keepends=True)
    target = next(i for i, ln in enumerate(lines) if ln.startswith("0002|")) + 100 * 3
    target = max(i for i in range(target) if "Xstart" in lines[i])
    edited = "".join(lines[:target]) + lines[target].replace("Xstart", "Xstert") + "".join(lines[target + 1:])
    unchanged = {id(r) for r in program.rungs}
    program2, _ = incremental.read(edited)
    assert incremental.last_mode == "window"
    first, last = incremental.last_window
    assert last - first < 20
    kept = sum(1 for r in program2.rungs if id(r) in unchanged)
    assert kept == len(program.rungs) - 1  # every rung but the edited one is the same object
    same(IncrementalReader("ladder"), edited)


def test_a_new_line_moves_the_rungs_below_without_reading_them():
    text = big_text()
    incremental = IncrementalReader("ladder")
    incremental.read(text)
    lines = text.splitlines(keepends=True)
    target = len(lines) // 3
    while not lines[target].startswith("    ||"):
        target += 1
    edited = "".join(lines[:target] + [lines[target]] + lines[target:])
    program, problems = incremental.read(edited)
    assert incremental.last_mode == "window"
    expected = fresh(edited)
    assert snapshot((program, problems)) == snapshot(expected)


def test_a_name_line_added_twice_reads_the_rung_above_with_it():
    """A rung's name line copied below itself (the benchmark's line added
    above catalog's QUAD ENCOD rung) is no longer right above the rung's
    number: the first copy would continue the rung before, so that rung is
    read again with it, rather than the whole diagram, and both read as a
    fresh reader reads them; removing the line reads a window again."""
    text = big_text()
    incremental = IncrementalReader("ladder")
    incremental.read(text)
    lines = text.splitlines(keepends=True)
    number = next(i for i in range(len(lines) // 2, len(lines)) if lines[i][:4].strip().isdigit())
    edited = "".join(lines[:number] + [lines[number - 1]] + lines[number:])
    assert lines[number - 1].strip("| \n")  # a name line
    program, problems = incremental.read(edited)
    assert incremental.last_mode == "window"
    first, last = incremental.last_window
    assert last - first < 20
    assert snapshot((program, problems)) == snapshot(fresh(edited))
    incremental.read(text)
    assert incremental.last_mode == "window"


def test_details_follow_the_text():
    incremental = IncrementalReader("ladder")
    with_details = EXAMPLE + "\nDETAILS:\n  TON Twarn: adjust -1\n"
    program, _ = incremental.read(with_details)
    assert [e.args["adjust"] for _, e in program.elements() if e.kind == "TON"] == [-1]
    program, _ = incremental.read(EXAMPLE)
    assert [e.args["adjust"] for _, e in program.elements() if e.kind == "TON"] == [0]


def test_random_edits_of_a_larger_text():
    import random

    rng = random.Random(7)
    for _ in range(40):
        text = big_text(24)
        incremental = IncrementalReader("ladder")
        same(incremental, text)
        for _ in range(5):
            step = (rng.choice(["type", "delete", "line-dup", "line-del", "replace"]), rng.randrange(10**6),
                    rng.randrange(10**6), rng.choice(EDIT_CHARS))
            text = apply(text, step)
            same(incremental, text)


def test_format_read_matches_the_formatter():
    from ide.incremental import format_read

    for text in corpus_texts():
        program, problems = IncrementalReader("ladder").read(text)
        assert format_read(text, program, problems) == fresh_format(text)


def fresh_format(text: str):
    from lang.textform.formatter import format_text

    return format_text(text)[0]


def test_a_locator_built_on_the_one_before_equals_a_new_one():
    import random

    from ide.locate import Locator

    rng = random.Random(5)
    for _ in range(20):
        text = big_text(24)
        incremental = IncrementalReader("ladder")
        program, _ = incremental.read(text)
        locator = Locator(program, text.splitlines())
        for _ in range(6):
            step = (rng.choice(["type", "delete", "line-dup", "line-del", "replace"]), rng.randrange(10**6),
                    rng.randrange(10**6), rng.choice(EDIT_CHARS))
            text = apply(text, step)
            program, _ = incremental.read(text)
            lines, titles = incremental.split()
            locator = Locator(program, lines, "ladder", locator, incremental.moved, titles=titles)
            fresh = Locator(program, text.splitlines())
            assert locator.rung_extents() == fresh.rung_extents()
            assert lines == text.splitlines() and locator.sections == fresh.sections  # the reader's split


def test_a_rung_nested_a_thousand_deep_moves_when_a_line_is_added_above():
    from test_deep_programs import deep_program

    from lang.dump import dumps

    text = render_program(deep_program())
    incremental = IncrementalReader("ladder")
    incremental.read(text)
    lines = text.splitlines(keepends=True)
    at = next(i for i, line in enumerate(lines) if line.startswith("LADDER DIAGRAM")) + 1
    edited = "".join(lines[:at] + ["\n"] + lines[at:])
    program, problems = incremental.read(edited)
    assert incremental.moved  # moved, not read again
    expected_program, expected_problems = fresh(edited)
    assert dumps(program) == dumps(expected_program)  # every span included, written without recursion
    assert problems == expected_problems
