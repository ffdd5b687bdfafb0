"""Programs as large as LDmicro holds. LDmicro bounds each series and each
parallel to 63 entries (MAX_ELEMENTS_IN_SUBCKT), not a rung's height nor how
deep blocks nest: a rung thousands of lines tall and blocks nested a thousand
deep are programs, and every command takes them whole, in seconds, without a
traceback."""

from __future__ import annotations

import json
import time
from functools import cache

from builders import coil, contact
from hypothesis import given
from hypothesis import strategies as st

from ladder.cli import main
from lang.dump import dumps, json_text, program_json
from lang.ldfile import MAX_ENTRIES, write_ld
from lang.model import Parallel, Program, Rung, Series
from lang.textform.reader import read_text
from lang.textform.writer import render_program

SECONDS = 10  # per command, on a machine busy with other tests
DEEP = 500  # parallels, each in a series in a branch of the one above: 1,000 levels


def tall_program(groups: int = 26, each: int = 20) -> Program:
    """One rung of groups * each branches (3 lines each), no block over
    LDmicro's 63 entries, so that LDmicro loads it as an .ld too."""
    assert groups <= MAX_ENTRIES and each <= MAX_ENTRIES
    branches = [Series([contact(f"Xg{g}"), Parallel([contact(f"Xa{g}_{k}") for k in range(each)])])
                for g in range(groups)]
    return Program(rungs=[Rung(Series([Parallel(branches), coil("Yout")]))])


def deep_program(levels: int = DEEP) -> Program:
    """`levels` parallels, each in the lower branch of the one above, with an
    element beside it in that branch alternately on its left and its right:
    the drawing stays `levels` cells wide and tall and its connectors short."""
    inner = Parallel([contact("Xa0"), contact("Xb0")])
    for level in range(1, levels):
        beside = contact(f"Xa{level}")
        inner = Parallel([contact(f"Xb{level}"), Series([beside, inner] if level % 2 else [inner, beside])])
    return Program(rungs=[Rung(Series([inner, coil("Yout")]))])


@cache
def _texts(shape: str) -> tuple[str, str]:
    program = tall_program() if shape == "tall" else deep_program()
    return render_program(program), write_ld(program)


def _files(tmp_path, shape: str):
    ladder_text, ld_text = _texts(shape)
    (tmp_path / "p.ladder").write_text(ladder_text, encoding="utf-8")
    (tmp_path / "p.ld").write_text(ld_text, encoding="cp1252")
    return tmp_path / "p.ladder", tmp_path / "p.ld"


def _ok(capsys, *argv) -> str:
    """The output of a command that must succeed, in time."""
    started = time.perf_counter()
    status = main([str(a) for a in argv])
    elapsed = time.perf_counter() - started
    out, err = capsys.readouterr()
    assert status == 0 and elapsed < SECONDS, (argv[0], status, f"{elapsed:.1f} s", (out + err)[-2000:])
    return out


def _every_command(capsys, tmp_path, shape: str) -> None:
    source, ld = _files(tmp_path, shape)
    text = source.read_text(encoding="utf-8")
    _ok(capsys, "check", source)
    _ok(capsys, "fmt", "--check", source)
    dumped = _ok(capsys, "dump", source)
    assert dumped.endswith("}\n") and dumped.count('"element": "CONTACTS"') == text.count("] [") > 0
    _ok(capsys, "convert", source, tmp_path / "back.ld")
    _ok(capsys, "convert", tmp_path / "back.ld", tmp_path / "back.ladder")
    _ok(capsys, "convert", ld, tmp_path / "from_ld.ladder")
    for converted in ("back.ladder", "from_ld.ladder"):
        assert (tmp_path / converted).read_text(encoding="utf-8") == text


def test_a_rung_of_1500_lines_reads_back_as_written():
    program = tall_program()
    text = render_program(program)
    assert sum("||" in line for line in text.splitlines()) > 1500
    read, problems = read_text(text)
    assert problems == [] and read.rungs == program.rungs


def test_every_command_takes_a_rung_of_1500_lines(capsys, tmp_path):
    _every_command(capsys, tmp_path, "tall")
    _ok(capsys, "check", tmp_path / "p.ld")  # no block over LDmicro's 63 entries


def test_every_command_takes_blocks_nested_a_thousand_deep(capsys, tmp_path):
    _every_command(capsys, tmp_path, "deep")


def test_dump_writes_blocks_nested_a_thousand_deep():
    text = dumps(deep_program())
    # the innermost contact: every block is two JSON levels (its object, its list)
    innermost = "\n" + "  " * (4 * DEEP + 4) + '"element": "CONTACTS",\n'
    assert innermost in text and text.count('"parallel": [') == DEEP


def test_dump_is_json_dumps_byte_for_byte():
    program = tall_program(3, 4)
    assert dumps(program) == json.dumps(program_json(program), indent=2, ensure_ascii=False) + "\n"


_SCALARS = st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text()


@given(st.recursive(_SCALARS, lambda inner: st.lists(inner) | st.dictionaries(st.text(), inner), max_leaves=30))
def test_json_text_is_json_dumps(value):
    assert json_text(value) == json.dumps(value, indent=2, ensure_ascii=False)
