"""Checking again after an edit (lang.checks.incremental, what the language
server does on every keystroke) gives what checking the new program whole
gives — diagnostics, their order, places, related places and fixes — and its
symbol table equals a fresh one; an edit inside one rung is checked as an edit."""

from __future__ import annotations

import random

from builders import coil, contact, program, timer
from generators import programs
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_lsp_incremental import EDIT_CHARS, EXAMPLE, apply, big_text, edits

from ide.incremental import IncrementalReader
from lang.checks import Checker, check_program
from lang.index import ProgramIndex
from lang.textform.writer import render_program


def full(diagnostics):
    return [(d, d.fixes) for d in diagnostics]


def table(index: ProgramIndex):
    """Everything in a symbol table, elements by identity (dicts in any order)."""
    def pairs(items):
        return [(rung, id(element)) for rung, element in items]

    def entries(by_name):
        return {name: [(u[1], id(u[2])) + tuple(u[3:]) if hasattr(u, "access") else (u[1], u[2], id(u[3]), u[4])
                       for u in items] for name, items in by_name.items()}

    return (pairs(index.elements), {kind: pairs(items) for kind, items in index.by_kind.items()},
            entries(index.uses), entries(index.marks),
            [(lit.text, lit.rung, id(lit.element), lit.field) for lit in index.literals],
            [(rung, id(series)) for rung, series in index.series],
            [(rung, id(series), position) for rung, series, position in index.followed])


class Session:
    """A document edited in the language server: read incrementally, checked incrementally."""

    def __init__(self):
        self.reader = IncrementalReader("ladder")
        self.checker = Checker()

    def same(self, text: str) -> None:
        program, _ = self.reader.read(text)
        assert full(self.checker.check(program, self.reader.moved)) == full(check_program(program))
        assert table(self.checker.index) == table(ProgramIndex(program))


@settings(max_examples=150, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(data=st.data())
def test_edits_of_the_example(data):
    session = Session()
    text = EXAMPLE + "\nDETAILS:\n  TON Twarn: adjust -1\n"
    session.same(text)
    for step in data.draw(edits(text)):
        text = apply(text, step)
        session.same(text)


@settings(max_examples=80, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large], deadline=None)
@given(program=programs(), data=st.data())
def test_edits_of_generated_programs(program, data):
    text = render_program(program)
    session = Session()
    session.same(text)
    for step in data.draw(edits(text)):
        text = apply(text, step)
        session.same(text)


def test_random_edits_of_a_larger_text():
    rng = random.Random(11)
    for _ in range(30):
        text = big_text(24)
        session = Session()
        session.same(text)
        for _ in range(6):
            step = (rng.choice(["type", "delete", "line-dup", "line-del", "replace"]), rng.randrange(10**6),
                    rng.randrange(10**6), rng.choice(EDIT_CHARS))
            text = apply(text, step)
            session.same(text)


def test_an_edit_in_one_rung_is_checked_as_an_edit():
    text = big_text(200)
    session = Session()
    session.same(text)
    assert session.checker.last == "whole"
    lines = text.splitlines(keepends=True)
    target = max(i for i in range(len(lines) // 2) if "Xstart" in lines[i])
    for new in ("Xstert", "Xstart"):
        lines[target] = lines[target].replace("Xstart" if new == "Xstert" else "Xstert", new)
        session.same("".join(lines))
        assert session.checker.last == "edit"
    blank = next(i for i in range(target, len(lines)) if lines[i].strip().replace(" ", "") == "||||")
    lines.insert(blank, lines[blank])  # a line added: the rungs below move
    session.same("".join(lines))
    assert session.checker.last == "edit"


def test_a_rename_offered_follows_the_names_used_elsewhere():
    text = render_program(program([contact("Xa"), coil("lamp")], [contact("Xb"), coil("Rx")]))
    session = Session()
    session.same(text)
    offered = [f.change.new for d in session.checker.check(session.reader.read(text)[0]) for f in d.fixes]
    assert "Rlamp" in offered
    session.same(text.replace("Rx   ", "Rlamp"))  # now used: no longer offered for rung 1
    session.same(text)


def test_versions_read_but_not_checked_in_between():
    """The server reads every version (a hover, the semantic tokens) but checks
    only some: the moves of the versions in between add up."""
    from ide.analysis import moved_since

    text = big_text(200)
    reader, checker = IncrementalReader("ladder"), Checker()
    checker.check(reader.read(text)[0])
    lines = text.splitlines(keepends=True)
    blanks = [i for i, line in enumerate(lines) if line.strip().replace(" ", "") == "||||"]
    moved: dict = {}
    program = checker.index.program
    for at in (blanks[40], blanks[10], blanks[60] + 1):  # rungs below move 1, 2 or 3 lines
        lines.insert(at, lines[at])
        previous, (program, _) = program, reader.read("".join(lines))
        moved = moved_since(moved, program, reader.moved, previous)
    assert full(checker.check(program, moved)) == full(check_program(program))
    assert checker.last == "edit"


def counted_edit(monkeypatch, text: str, name: str, at: int, typed: str):
    """What the language server does after a one-character edit (`typed`
    over character `at` of the first `name` drawn), counted: the rungs the
    reader parses, the symbol table walks, the rules that look at rungs see
    and DETAILS names. Returns the counts, the diagnostics checked again and
    the new program with its reading problems."""
    from lsprotocol import types

    import lang.textform.reader as reader_module
    from lang.checks import incremental
    from lang.textform import details
    from lsp.text import LineDocument

    document = LineDocument("file:///big.ladder", text)
    reader, checker = IncrementalReader("ladder"), Checker()
    checker.check(reader.read(document.source, document.take_edited())[0], reader.moved)

    counted = {"rungs parsed": 0, "rungs indexed": 0, "rungs a rule saw": 0, "rungs DETAILS named": 0}

    def counting(key, function, how_many):
        def counted_call(*args, **kwargs):
            counted[key] += how_many(*args, **kwargs)
            return function(*args, **kwargs)
        return counted_call

    monkeypatch.setattr(reader_module, "read_rung", counting("rungs parsed", reader_module.read_rung, lambda *a: 1))
    monkeypatch.setattr(ProgramIndex, "_build", counting(
        "rungs indexed", ProgramIndex._build, lambda self, program, rungs: len(list(rungs))))
    monkeypatch.setattr(details, "element_names", counting("rungs DETAILS named", details.element_names, lambda *a: 1))
    rung_rules = tuple(counting("rungs a rule saw", rule, lambda program, index: len(list(index.rungs)))
                       for rule in incremental.BY_SCOPE[incremental.RUNGS])
    monkeypatch.setitem(incremental.BY_SCOPE, incremental.RUNGS, rung_rules)

    line = next(n for n, text_line in enumerate(document.lines) if f"{name} " in text_line)
    col = document.lines[line].index(name) + at
    document.apply_change(types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(line=line, character=col),
                          end=types.Position(line=line, character=col + 1)), text=typed))
    program_after, problems = reader.read(document.source, document.take_edited())
    found = checker.check(program_after, reader.moved)
    assert checker.last == "edit" and reader.last_mode == "window"
    return {key: value // len(rung_rules) if key == "rungs a rule saw" else value
            for key, value in counted.items()}, found, program_after, problems


def test_an_edit_of_one_rung_of_18000_touches_that_rung_only(monkeypatch):
    """After a one-character edit the reader parses the edited rung alone,
    the symbol table walks it alone (as it was and as it is), the rules that
    look at rungs see it alone, and DETAILS looks at its elements alone."""
    rungs = [[contact(f"X{n}"), contact(f"R{n}", negated=1), coil(f"R{n + 1}")] for n in range(18_000)]
    rungs[5] = [contact("X5"), timer("TON", "T5", 100_000), coil("R6")]
    text = render_program(program(*rungs)) + "\nDETAILS:\n  TON T5: adjust -1\n"
    counted, found, program_after, problems = counted_edit(monkeypatch, text, "R9000", 1, "Q")
    assert counted == {"rungs parsed": 1, "rungs indexed": 2, "rungs a rule saw": 2, "rungs DETAILS named": 1}
    assert found == check_program(program_after) and not [p for p in problems if p.severity == "error"]


def test_a_name_that_comes_into_use_touches_the_rungs_its_rename_is_offered_in_only(monkeypatch):
    """A fix offers to rename a name only to one the program does not use
    (`Rename 'c' to 'Xc'` on a contact named without a role letter): an edit
    that brings `Xc` into use, or takes it out of use, changes that fix, in
    the one rung that has it. The thousand rungs that use `Rc`, whose rename
    to `Xc` could be offered too but is not (nothing is wrong with them), are
    not looked at again (the benchmark's edit of a converted program, whose
    copies read the same inputs, `Xa` typed over as `Xc`, brought 401 rungs of
    2,000 to be checked and 1,996 indexed again)."""
    rungs = [[contact("Xa"), contact(f"R{n}", negated=1), coil(f"R{n + 1}")] if n % 2 else
             [contact("Xa"), contact("Rc"), coil(f"R{n + 1}")] for n in range(2_000)]
    rungs[0] = [contact("Xa"), coil("Rc")]
    rungs[1] = [contact("c"), coil("R2")]
    rungs[1_001] = [contact("Xb"), contact("R1001", negated=1), coil("R1002")]
    text = render_program(program(*rungs))
    for name, typed in (("Xb", "c"), ("Xc", "b")):  # Xc comes into use, then goes out of it
        counted, found, program_after, _ = counted_edit(monkeypatch, text, name, 1, typed)
        monkeypatch.undo()
        assert counted == {"rungs parsed": 1, "rungs indexed": 4, "rungs a rule saw": 4, "rungs DETAILS named": 0}
        assert full(found) == full(check_program(program_after))
        assert ("Xc" in [f.change.new for d in found for f in d.fixes]) == (typed == "b")
        text = render_program(program_after)


def test_a_rung_edited_again_runs_the_rules_of_its_names_once(monkeypatch):
    """A name typed over and back in one rung whose input a thousand rungs
    read (`Xa`): after the first edit, the rules of the names the edit
    touched run on the new program only; what they gave on the old one is
    what the edit before found."""
    from lang.checks import incremental

    rungs = [[contact("Xa"), contact(f"R{n}", negated=1), coil(f"R{n + 1}")] for n in range(1_000)]
    rungs[500] = [contact("Xa"), contact("Xb"), coil("R501")]
    text = render_program(program(*rungs))
    reader, checker = IncrementalReader("ladder"), Checker()
    checker.check(reader.read(text)[0], reader.moved)
    runs = []
    rules = tuple((lambda check: lambda program, index: runs.append(check) or check(program, index))(rule)
                  for rule in incremental.BY_SCOPE[incremental.NAMES])
    monkeypatch.setitem(incremental.BY_SCOPE, incremental.NAMES, rules)
    for step, (old, new) in enumerate((("Xb ", "Xc "), ("Xc ", "Xb "), ("Xb ", "Xc "), ("Xc ", "Xb "))):
        text = text.replace(old, new)
        edited = reader.read(text)[0]
        runs.clear()
        found = checker.check(edited, reader.moved)
        assert checker.last == "edit" and len(runs) == (2 if step == 0 else 1) * len(rules)
        assert full(found) == full(check_program(edited))


@settings(max_examples=150, suppress_health_check=[HealthCheck.too_slow], deadline=None)
@given(data=st.data())
def test_edits_checked_now_and_then(data):
    """As the server does while typing: every version is read, only some are
    checked, the moves of those in between composed (ide.analysis.moved_since)."""
    from ide.analysis import moved_since

    reader, checker = IncrementalReader("ladder"), Checker()
    text = big_text(24)
    program = reader.read(text)[0]
    checker.check(program)
    moved: dict = {}
    for step in data.draw(edits(text)):
        text = apply(text, step)
        previous, (program, _) = program, reader.read(text)
        moved = moved_since(moved, program, reader.moved, previous)
        if data.draw(st.booleans()):
            assert full(checker.check(program, moved)) == full(check_program(program))
            moved = {}
    assert full(checker.check(program, moved)) == full(check_program(program))


def test_an_edit_of_the_io_table_is_checked_as_an_edit():
    """A pin changed in the I/O table checks again the rungs that use that
    name and the name itself, not the whole program."""
    session = Session()
    text = big_text(40)
    session.same(text)
    row = next(line for line in text.splitlines() if line.startswith("  Xstop "))
    for edited in (text.replace(row, row.replace("|   5 |", "|   4 |")),  # Xstart's pin too: LD401
                   text.replace(row, row.replace("|   5 | PD3", "|     |    ")),  # no pin at all
                   text):
        assert edited == text or row not in edited
        session.same(edited)
        assert session.checker.last == "edit"
