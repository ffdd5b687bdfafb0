"""The editor features of ide/ on plain values, without a server: the parts
whose logic the wire tests (tests/test_lsp_*.py) reach only through a few
cases. Edits are applied to the text and the result read again, as an editor
would."""

from __future__ import annotations

from pathlib import Path

import pytest

from ide import completion, edits
from ide.analysis import Analysis
from ide.formatting import format_edits, line_edits
from ide.session import SessionError, Simulation
from ide.tokens import TokenType, rung_tokens
from lang.diagnostics import ERROR
from lang.loader import TEXT_KIND, parse
from lang.textform.formatter import format_text

CONVEYOR = (Path(__file__).resolve().parents[1] / "examples" / "conveyor.ladder").read_text()


def read(text: str) -> Analysis:
    """A document read whole, as the language server's first read of it."""
    return Analysis(TEXT_KIND, text, *parse(text, TEXT_KIND))


def apply(text: str, changes: list[edits.RangeEdit]) -> str:
    """The text with the edits made (they do not overlap), "\n" line ends."""
    lines = text.split("\n")
    starts = [0]
    for line in lines:
        starts.append(starts[-1] + len(line) + 1)

    def offset(line: int, col: int) -> int:
        assert 0 <= line < len(lines) and 0 <= col <= len(lines[line]), (line, col)
        return starts[line] + col

    for change in sorted(changes, key=lambda c: (c.span.line, c.span.col), reverse=True):
        start, end = offset(change.span.line, change.span.col), offset(change.span.end_line, change.span.end_col)
        text = text[:start] + change.text + text[end:]
    return text


# --- formatting ---------------------------------------------------------------------------------

@pytest.mark.parametrize("old, new", [
    ("a\nb\nc\n", "a\nB\nc\n"),
    ("a\nb\nc\n", "a\nb\nc\nd\ne\n"),  # lines added after the last
    ("a\nb\nc\n", "a\nb\nC\nD\n"),  # the last line changed
    ("a\nb\nc\nd\n", "a\nd\n"),
    ("a\nb\nc\n", "x\ny\n"),
])
def test_the_formatters_line_edits_make_the_new_text_and_stay_inside_the_buffer(old, new):
    found = line_edits(old, new)
    assert apply(old, found) == new
    # an edit that reached past the last line would make Neovim add a line
    assert all(e.span.end_line < len(old.splitlines()) for e in found)


def test_formatting_a_misaligned_program_gives_what_ladder_fmt_gives():
    misaligned = CONVEYOR.replace("  Xstart                     | digital in", "  Xstart | digital in")
    document = read(misaligned)
    found = format_edits(document.text, document.program, document.problems)
    assert found and apply(misaligned, found) == format_text(misaligned)[0] == CONVEYOR
    broken = misaligned.replace("( )", "( ", 1)
    assert format_edits(broken, *parse(broken, TEXT_KIND)) is None


# --- completion: an element inserted on a wire -----------------------------------------------

def _rung_kinds(text: str, index: int) -> list[str]:
    program, problems = parse(text, TEXT_KIND)
    assert not [p for p in problems if p.severity == ERROR], problems
    return [e.kind for e in program.rungs[index].elements()]


def test_each_element_inserted_on_a_wire_redraws_the_rung_around_the_cursors_line():
    document = read(CONVEYOR)
    line = next(n for n, text in enumerate(document.lines) if text.startswith("0002"))
    col = document.line(line).index("] [") + 6  # on the wire after Xstart, in the first of the rung's rows
    found = completion.complete(document, line, col, snippets=False)
    assert found is not None and len(found.items) > 10
    before = _rung_kinds(CONVEYOR, 1)
    assert before == ["CONTACTS", "CONTACTS", "CONTACTS", "COIL"]  # Xstart, Rrun below it, Xstop, Rrun
    for item in found.items:
        assert item.edit.span.line == item.edit.span.end_line == line  # the main edit: the cursor's line
        assert item.more  # the rung's other rows
        changed = apply(CONVEYOR, [item.edit, *item.more])
        kinds = _rung_kinds(changed, 1)
        assert kinds == before[:1] + [edits.COMMON[int(item.sort or "")]] + before[1:], item.label
        assert _rung_kinds(changed, 2) == _rung_kinds(CONVEYOR, 2)  # the next rung is left alone


# --- the simulation session ------------------------------------------------------------------

def test_a_session_runs_toggles_and_reloads_an_edit_keeping_the_values():
    simulation = Simulation(read(CONVEYOR))
    assert simulation.state().scan == 1
    simulation.toggle("Xstart")
    simulation.step(1)
    assert simulation.value("Rrun") == 1 and simulation.value("Xnone") is None
    state = simulation.state()
    assert state.values["Rrun"] == 1 and state.energized and state.error is None
    simulation.reload(read(CONVEYOR.replace("( )", "( ", 1)))
    assert simulation.error is not None and simulation.value("Rrun") == 1  # did not read: the last one runs
    edited = read(CONVEYOR.replace("[TON 2 s]", "[TON 3 s]"))
    simulation.reload(edited)
    assert simulation.error is None and simulation.document is edited
    assert simulation.value("Rrun") == 1  # sealed in, kept
    with pytest.raises(SessionError, match="Xnone"):
        simulation.set("Xnone", 1)
    with pytest.raises(SessionError):
        simulation.condition("Xnone = 1")
    with pytest.raises(SessionError):
        simulation.condition("Rrun ~ 1")


def test_running_until_a_condition_stops_at_the_limit_or_when_it_holds():
    simulation = Simulation(read(CONVEYOR))
    simulation.toggle("Xstart")
    reached = simulation.run_until(simulation.condition("Ymotor = 1"), 10_000.0, 5.0)
    assert reached and 2000 <= simulation.state().time_ms <= 2100  # the 2 s horn, then the motor
    never = simulation.condition("Xstop = 1")
    assert not simulation.run_until(never, simulation.state().time_ms + 50, 5.0)
    assert simulation.state().time_ms >= 2050


def test_a_session_shows_the_values_after_each_line_a_name_is_on():
    document = read(CONVEYOR)
    simulation = Simulation(document)
    hints = simulation.hints(document, 0, len(document.lines))
    lines = [h.line for h in hints]
    assert lines == sorted(set(lines))
    assert all(h.col == len(document.line(h.line)) for h in hints)
    start_row = next(h for h in hints if "Xstart=" in h.label)
    assert start_row.label == "Xstart=0  Xstop=0  Rrun=0"  # left to right


def test_a_program_with_errors_is_not_simulated():
    with pytest.raises(SessionError, match="errors"):
        Simulation(read(CONVEYOR.replace("( )", "( ", 1)))


# --- semantic tokens --------------------------------------------------------------------------

def test_a_rungs_tokens_are_in_order_apart_and_mark_the_names_it_writes():
    document = read(CONVEYOR)
    for index in range(len(document.program.rungs)):
        found = rung_tokens(document, index)
        assert found == sorted(found)
        for before, after in zip(found, found[1:]):
            assert (before.line, before.col + before.length) <= (after.line, after.col)
        for token in found:
            assert token.col + token.length <= len(document.line(token.line))
    tokens = [(document.line(t.line)[t.col:t.col + t.length], t.type, t.writes) for t in rung_tokens(document, 1)]
    assert ("Rrun", TokenType.VARIABLE, True) in tokens and ("Rrun", TokenType.VARIABLE, False) in tokens
    assert ("Xstart", TokenType.PARAMETER, False) in tokens and ("0002", TokenType.NUMBER, False) in tokens


def test_edits_of_a_program_of_more_than_9999_rungs_keep_its_wider_margin():
    """Redrawn and inserted rungs get the five-digit margin the formatter
    gives such a program (lang.textform.writer.margin_width)."""
    from builders import coil, contact

    from ide.fixes import apply_edits
    from ide.locate import Locator
    from lang.model import Program, Rung, Series
    from lang.textform.reader import read_text
    from lang.textform.writer import render_program

    text = render_program(Program(rungs=[Rung(Series([contact(f"X{n}"), coil(f"Y{n}")])) for n in range(10_000)]))
    program, _ = read_text(text)
    locator = Locator(program, text.splitlines())
    changed = [edits.redraw(locator, text, 9_999, Rung(Series([contact("Xnew"), coil("Ynew")]))),
               edits.insert_rung(locator, text, 10_000, edits.new_rung())]
    for edit in changed:
        after = apply_edits(text, [edit], [])
        read, problems = read_text(after)
        assert not problems, problems[:3]
        assert len({line.index("||") for line in after.splitlines()[1:] if "||" in line}) == 1


def test_the_names_offered_follow_the_edits_that_bring_names_in_and_out():
    """ide.names keeps the sorted names from one version to the next, until
    an edit brings a name into use or takes one out of it."""
    from ide.incremental import IncrementalReader
    from ide.names import candidates
    from lang.checks import Checker

    reader, checker = IncrementalReader("ladder"), Checker()

    def offered(text: str, typed: str) -> list[str]:
        program, _ = reader.read(text)
        checker.check(program, reader.moved)
        return candidates(program, checker.index, "CONTACTS", "name", typed)

    assert offered(CONVEYOR, "Rru") == ["Rrun"]
    renamed = CONVEYOR.replace("Rrun      ", "Rrunning  ", 1)
    assert offered(renamed, "Rru") == ["Rrun", "Rrunning"]
    assert checker.last == "edit"
    assert offered(CONVEYOR, "Rru") == ["Rrun"]
    assert candidates(checker.index.program, checker.index, "COIL", "name", "X") == []  # a coil drives no input
    every = offered(CONVEYOR, "")  # nothing typed: every bit name, in order, asked twice of one version
    assert every == sorted(every) and "Rrun" in every and {name[0] for name in every} <= set("XYRPIM")
    assert candidates(checker.index.program, checker.index, "CONTACTS", "name", "") == every
