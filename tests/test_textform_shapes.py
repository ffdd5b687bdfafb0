"""Rungs of one shape with other names, as a converted program repeats
them: each reads to its own circuit, with its own names at its own places,
however many rungs share the shape, and an edit of one leaves the others as
they were (the reader builds a shape it has reduced before from a plan:
lang/textform/circuit.py)."""

from __future__ import annotations

from ide.incremental import IncrementalReader
from lang.model import Element, Parallel, Program, Rung, Series, Settings
from lang.textform import rungs
from lang.textform.elements import complete_args
from lang.textform.reader import read_text
from lang.textform.writer import render_program


def element(kind: str, name: str) -> Element:
    return Element(kind, complete_args(kind, {"name": name}))


def branchy(n: int) -> Rung:
    """Two contacts in series beside a third, in parallel, before two
    branches of coils: a shape the row reader alone cannot take."""
    contacts = Parallel([Series([element("CONTACTS", f"Xa{n}"), element("CONTACTS", f"Xb{n}")]),
                         element("CONTACTS", f"Xc{n}")])
    coils = Parallel([element("COIL", f"Ya{n}"), element("COIL", f"Yb{n}")])
    return Rung(Series([contacts, coils]))


def program_text(rungs: int) -> str:
    return render_program(Program(Settings(mcu="Atmel AVR ATmega328 28-PDIP"), [branchy(n) for n in range(rungs)]))


def names(rung: Rung) -> list[str]:
    return [str(e.args["name"]) for e in rung.elements()]


def test_every_rung_of_a_repeated_shape_reads_to_its_own_names_and_places():
    text = program_text(40)
    program, problems = read_text(text)
    assert not problems
    lines = text.splitlines()
    for n, rung in enumerate(program.rungs):
        assert names(rung) == [f"Xa{n}", f"Xb{n}", f"Xc{n}", f"Ya{n}", f"Yb{n}"]
        for e in rung.elements():
            at = e.arg_spans["name"]
            assert lines[at.line][at.col:at.end_col] == e.args["name"]
        first = rung.circuit.items[0]
        assert isinstance(first, Parallel) and isinstance(first.branches[0], Series)
        assert first.span is not None and rung.span is not None
        assert rung.span.line <= first.span.line and first.span.end_line <= rung.span.end_line


def test_an_edit_of_one_rung_of_a_shape_leaves_the_others_as_they_were():
    text = program_text(12)
    reader = IncrementalReader("ladder")
    before, _ = reader.read(text)
    kept = [names(rung) for rung in before.rungs]
    # a block of one rung changed in place must not show in another
    parallel = before.rungs[3].circuit.items[0]
    assert isinstance(parallel, Parallel)
    parallel.branches.reverse()
    assert names(before.rungs[4]) == kept[4]
    after, problems = reader.read(text.replace("Xb5 ", "Xq5 ", 1))
    assert not problems
    assert names(after.rungs[5]) == ["Xa5", "Xq5", "Xc5", "Ya5", "Yb5"]
    assert [names(rung) for n, rung in enumerate(after.rungs) if n not in (3, 5)] == \
        [kept[n] for n in range(12) if n not in (3, 5)]


def placed(program: Program) -> list[list[tuple]]:
    return [[(e.kind, e.args, e.span, e.arg_spans) for e in rung.elements()] for rung in program.rungs]


def test_a_copy_that_names_no_instruction_or_moves_a_name_reads_as_if_alone(monkeypatch):
    """A rung whose skeleton was read before is made from that read's recipe
    (lang/textform/rungs.py): a copy whose name makes no instruction still
    gets its error at its glyph, and a name moved over its glyph its place."""
    text = program_text(6)
    text = text.replace(" Xb3 ", " X-3 ", 1)  # no contact is named so
    text = text.replace("       Xc4", "     Xc4  ", 1)  # two columns left, still over its contact
    program, problems = read_text(text)
    lines = text.splitlines()
    assert [(p.code, lines[p.span.line][p.span.col:p.span.end_col]) for p in problems] == [("LD003", "] [")]
    assert problems[0].span.line == next(n for n, line in enumerate(lines) if line.startswith("0004"))
    moved = next(e for e in program.rungs[4].elements() if e.args["name"] == "Xc4")
    at = moved.arg_spans["name"]
    assert lines[at.line][at.col:at.end_col] == "Xc4" and moved.span is not None and moved.span.col == at.col
    monkeypatch.setattr(rungs, "_RECIPES", {})  # every rung read in full
    alone, alone_problems = read_text(text)
    assert placed(program) == placed(alone) and problems == alone_problems



def test_a_copy_whose_element_ends_its_drawing_reads_as_if_alone(monkeypatch):
    """A rung made from a recipe takes the characters either side of each
    glyph from the recipe (lang/textform/rungs.py `Cell`): past the drawing's
    right end one copy has its rail, another a blank or nothing, and each
    reads as it would alone."""
    lines = program_text(6).splitlines()
    coils = [n for n, line in enumerate(lines) if line.endswith("( )-------||")]
    for at, n in enumerate(coils):
        ending = ("||", "   ", "")[at % 3]
        lines[n] = lines[n].replace("( )-------||", "( )" + ending)
    text = "\n".join(lines) + "\n"
    program, problems = read_text(text)
    assert not problems
    monkeypatch.setattr(rungs, "_RECIPES", {})  # every rung read in full
    alone, alone_problems = read_text(text)
    assert placed(program) == placed(alone) and not alone_problems
    coil = next(e for e in program.rungs[5].elements() if e.kind == "COIL")
    at = coil.arg_spans["name"]
    assert text.splitlines()[at.line][at.col:at.end_col] == coil.args["name"]

def blocks(node) -> tuple:
    """A circuit's blocks and elements with their places."""
    if isinstance(node, Element):
        return (node.kind, node.span)
    kids = node.items if isinstance(node, Series) else node.branches
    return (type(node).__name__, node.span, tuple(blocks(kid) for kid in kids))


def test_the_blocks_of_a_copy_stand_where_they_would_read_alone(monkeypatch):
    """A copy's blocks are placed from its recipe (lang/textform/circuit.py
    `build_at`): each spans its own elements, as if the rung were reduced."""
    text = program_text(8)
    program, _ = read_text(text)
    monkeypatch.setattr(rungs, "_RECIPES", {})  # every rung read in full
    alone, _ = read_text(text)
    assert [blocks(rung.circuit) for rung in program.rungs] == [blocks(rung.circuit) for rung in alone.rungs]
    spans = [rung.circuit.items[0].span for rung in program.rungs]
    assert len(set(spans)) == len(spans)  # each copy's own lines
