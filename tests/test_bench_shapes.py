"""The programs benchmarks/lsp_bench.py opens, at a small size: each reads
without a problem, the I/O table shape has its rows, and every `.ld` file of
the corpus is a shape (or a copy of one) whose repeated copies keep the
original's pins."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from lang.checks import check_program
from lang.diagnostics import ERROR
from lang.loader import TEXT_KIND, load_path, parse

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

from lsp_bench import GENERATED, corpus_shapes, middle_name, selected, table_row  # noqa: E402
from shapes import corpus_root  # noqa: E402

RUNGS = 40
CORPUS_SHAPES, COPIES = corpus_shapes(corpus_root())


def read(text: str):
    program, problems = parse(text, TEXT_KIND)
    assert problems == []
    assert len(program.rungs) == RUNGS
    middle_name(text.splitlines(), RUNGS)  # the benchmark finds a name to edit
    return program


@pytest.mark.parametrize("shape", GENERATED, ids=lambda s: s.name)
def test_a_generated_shape_reads_and_checks_clean(shape):
    assert check_program(read(shape.text(RUNGS))) == []


def test_the_io_table_has_a_row_per_rung_and_the_edit_lands_in_it():
    lines = next(s for s in GENERATED if s.name == "io-table").text(200).splitlines()  # 80 pins, then Modbus
    title = lines.index("I/O ASSIGNMENT:")
    rows = lines[title + 3:lines.index("", title)]
    assert len(rows) == 200
    assert {row.split("|")[1].strip() for row in rows} == {"digital in", "digital out", "modbus contact", "modbus coil"}
    line, column = table_row(lines)
    assert lines[line] == rows[100] and lines[line][column + 1] == " "


def test_every_corpus_file_is_a_shape_or_a_copy_of_one():
    names = {s.name for s in CORPUS_SHAPES}
    files = sorted(corpus_root().rglob("*.ld"))
    assert len(CORPUS_SHAPES) + len(COPIES) == len(files) > 30
    assert all(original in names for _, original in COPIES)
    assert {name.split("/")[0] for name in names} == {"corpus:0.1", "corpus:0.2"}


def test_a_dialect_or_a_file_is_chosen_by_a_pattern():
    old, _ = selected(["corpus:0.1/*"], corpus_root())
    assert old and all(s.name.startswith("corpus:0.1/") for s in old)
    one, copies = selected(["corpus:*/sample/blink.ld"], corpus_root())
    assert [s.name for s in one] == ["corpus:0.1/ldmicro/sample/blink.ld"] and len(copies) == 1
    everything, _ = selected(["all"], corpus_root())
    assert len(everything) == len(GENERATED) + len(CORPUS_SHAPES)


@pytest.mark.parametrize("shape", CORPUS_SHAPES, ids=lambda s: s.name)
def test_a_corpus_file_repeated_reads_clean_and_adds_no_kind_of_error(shape):
    """Its copies' names are renamed but for those with a pin, so no copy
    lacks one (LD407) unless the original does."""
    repeated = read(shape.text(RUNGS))
    original, _ = load_path(corpus_root() / shape.name.split("/", 1)[1])
    errors = [{d.code for d in check_program(program) if d.severity == ERROR} for program in (repeated, original)]
    assert errors[0] <= errors[1]


def test_the_copies_keep_the_originals_parameters_the_drawing_does_not_show():
    """Only drawn names are renamed: an SPI element's mode stays `Master`
    (not `Master1`, `Master2`, ..., no mode at all, one DETAILS line per
    copy), so the copies' details are the original's."""
    shape = next(s for s in CORPUS_SHAPES if s.name.endswith("/test-spi.ld"))
    original, _ = load_path(corpus_root() / shape.name.split("/", 1)[1])
    undrawn = {(e.kind, f.name, e.args.get(f.name, f.default)) for _, e in original.elements()
               for f in e.spec.fields if not f.drawn}
    repeated = read(shape.text(RUNGS))
    assert {(e.kind, f.name, e.args.get(f.name, f.default)) for _, e in repeated.elements()
            for f in e.spec.fields if not f.drawn} == undrawn
    assert ("SPI", "mode", "Master") in undrawn


def test_the_cpu_mode_times_the_open_and_every_edit_of_a_shape():
    from lsp_bench import cpu_run

    shape = next(s for s in GENERATED if s.name == "io-table")
    samples = cpu_run(shape.text(RUNGS), RUNGS, 4)
    assert {measure: len(taken) for measure, taken in samples.items()} == {"open": 1, "edit": 4, "line": 4, "table": 4}
    assert all(ms >= 0 for taken in samples.values() for ms in taken)


def test_the_benchmark_names_the_python_it_runs_on_and_its_libpython():
    """The figures depend on the interpreter's build: a shared libpython
    made an open a fifth slower (docs/lsp.md, "Speed")."""
    import platform

    from lsp_bench import interpreter

    said = interpreter()
    assert said.startswith(f"Python {platform.python_version()} (")
    assert said.endswith(("libpython a shared library", "libpython linked in"))


@pytest.mark.slow
def test_the_benchmark_runs_at_the_wire_against_a_baseline_checkout():
    """One small run of the whole benchmark, this checkout's server against
    the server of a baseline checkout (here the same one): a row for each,
    the baseline's first, and the diagnostics its client read at the open as
    many as the checks find in the same text."""
    root = Path(__file__).resolve().parents[1]
    shape = next(s for s in CORPUS_SHAPES if s.name.endswith("Tests/test-spi.ld"))
    done = subprocess.run([sys.executable, str(root / "benchmarks" / "lsp_bench.py"), "--shape", shape.name,
                           "--rungs", str(RUNGS), "--runs", "1", "--edits", "20", "--storm-seconds", "1",
                           "--baseline", str(root)], capture_output=True, text=True, timeout=300, cwd=root)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.splitlines()
    table = next(n for n, line in enumerate(lines) if line.split()[:4] == ["shape", "rungs", "MB", "diags"])
    rows = [line.split() for line in lines[table + 1:] if line.startswith(shape.name)]
    assert [row[1] for row in rows] == ["[baseline]", str(RUNGS)]
    program, problems = parse(shape.text(RUNGS), TEXT_KIND)
    found = len(problems) + len(check_program(program))
    assert found > 0 and int(rows[0][4]) == int(rows[1][3]) == found
