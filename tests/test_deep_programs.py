"""Programs as large as LDmicro holds. LDmicro bounds each series and each
parallel to 63 entries (MAX_ELEMENTS_IN_SUBCKT), not a rung's height nor how
deep blocks nest: a rung thousands of lines tall and blocks nested a thousand
deep are programs, and every command takes them whole, in seconds, without a
traceback."""

from __future__ import annotations

import json
import random
import time
from dataclasses import replace
from functools import cache

import pytest
from builders import coil, contact
from c_harness import differential as c_differential
from hypothesis import given
from hypothesis import strategies as st
from pic16_harness import differential as pic16_differential
from test_compiler_harness import IN_CI, Event
from test_compiler_harness import differential as avr_differential

from compiler.run import c as c_run
from compiler.run import gpsim, simavr
from ladder.cli import main
from lang.dump import dumps, json_text, program_json
from lang.ldfile import MAX_ENTRIES, write_ld
from lang.model import Parallel, PinAssignment, Program, Rung, Series, Settings
from lang.sim import Simulator
from lang.textform.reader import read_text
from lang.textform.writer import render_program

SECONDS = 10  # per command, on a machine busy with other tests
DEEP = 500  # parallels, each in a series in a branch of the one above: 1,000 levels

needs_cc = pytest.mark.skipif(not c_run.available(), reason="no C compiler (Debian: gcc)")
needs_simavr = pytest.mark.skipif(not simavr.available() and not IN_CI, reason="gcc + libsimavr-dev not installed")
needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


def tall_program(groups: int = 26, each: int = 20) -> Program:
    """One rung of groups * each branches (3 lines each), no block over
    LDmicro's 63 entries, so that LDmicro loads it as an .ld too."""
    assert groups <= MAX_ENTRIES and each <= MAX_ENTRIES
    branches = [Series([contact(f"Xg{g}"), Parallel([contact(f"Xa{g}_{k}") for k in range(each)])])
                for g in range(groups)]
    return Program(rungs=[Rung(Series([Parallel(branches), coil("Yout")]))])


def deep_program(levels: int = DEEP, inputs: int = DEEP) -> Program:
    """`levels` parallels, each in the lower branch of the one above, with an
    element beside it in that branch alternately on its left and its right:
    the drawing stays `levels` cells wide and tall and its connectors short.
    The contacts read 2 * `inputs` inputs, fewer than `levels` for a part's pins."""
    inner = Parallel([contact("Xa0"), contact("Xb0")])
    for level in range(1, levels):
        beside = contact(f"Xa{level % inputs}")
        inner = Parallel([contact(f"Xb{level % inputs}"), Series([beside, inner] if level % 2 else [inner, beside])])
    return Program(rungs=[Rung(Series([inner, coil("Yout")]))])


def shallow_program(levels: int = DEEP) -> Program:
    """What deep_program computes, a rung a level: each level's output kept in a relay."""
    rungs = [Rung(Series([Parallel([contact("Xa0"), contact("Xb0")]), coil("Rlevel0")]))]
    for level in range(1, levels):
        below = Series([contact(f"Xa{level}"), contact(f"Rlevel{level - 1}")])
        rungs.append(Rung(Series([Parallel([contact(f"Xb{level}"), below]), coil(f"Rlevel{level}")])))
    rungs.append(Rung(Series([contact(f"Rlevel{levels - 1}"), coil("Yout")])))
    return Program(rungs=rungs)


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
    _ok(capsys, "sim", source, "--for", "100ms")
    _ok(capsys, "build", source, "--emit", "c")
    assert "PlcCycle" in (tmp_path / "p.c").read_text()


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


def test_blocks_nested_a_thousand_deep_simulate_as_a_rung_a_level():
    """Every Xa closed but one and every Xb open but one, both at levels drawn
    anew each scan: the coil has power when the closed Xb is at or above the
    open Xa, whatever the depth of either."""
    sims = Simulator(deep_program()), Simulator(shallow_program())
    rng = random.Random(1)
    changes = [(f"Xa{level}", 1) for level in range(DEEP)]
    cut = bypass = 0
    for _ in range(200):
        changes += [(f"Xa{cut}", 1), (f"Xb{bypass}", 0)]
        cut, bypass = rng.randrange(DEEP), rng.randrange(DEEP)
        changes += [(f"Xa{cut}", 0), (f"Xb{bypass}", 1)]
        for sim in sims:
            for name, value in changes:
                sim.set(name, value)
            sim.step()
        changes = []
        assert [sim.value("Yout") for sim in sims] == [int(bypass >= cut)] * 2


# deep_program(inputs=4) on parts, its names Xa0..Xa3, Xb0..Xb3 and Yout on pins
PINNED = 4
PARTS = {
    "avr": (Settings(mcu="Atmel AVR ATmega328 28-PDIP"), ("PD2", "PD3", "PD4", "PD5", "PD6", "PD7", "PB0", "PB1", "PB2")),
    "pic16": (Settings(mcu="Microchip PIC16F877 40-PDIP", crystal_hz=20_000_000),
              ("RB0", "RB1", "RB2", "RB3", "RB4", "RB5", "RB6", "RB7", "RD0")),
}


def _on_part(family: str) -> Program:
    settings, pins = PARTS[family]
    names = [f"X{side}{i}" for side in "ab" for i in range(PINNED)] + ["Yout"]
    program = replace(deep_program(inputs=PINNED), settings=settings)
    program.pins.update((name, PinAssignment(name, pin)) for name, pin in zip(names, pins))
    return program


def _stimulus(scans: int) -> list[Event]:
    rng = random.Random(2)
    return [Event(scan, f"X{side}{i}", rng.randint(0, 1))
            for scan in range(0, scans, 2) for side in "ab" for i in range(PINNED)]


@pytest.mark.parametrize("family", sorted(PARTS))
def test_blocks_nested_a_thousand_deep_build_for_a_part(family, capsys, tmp_path):
    source = tmp_path / "p.ladder"
    source.write_text(render_program(_on_part(family)), encoding="utf-8")
    _ok(capsys, "build", source)
    assert (tmp_path / "p.hex").stat().st_size > 0


@needs_cc
def test_blocks_nested_a_thousand_deep_run_in_c_as_simulated(tmp_path):
    assert c_differential(deep_program(inputs=PINNED), _stimulus(40), 40, tmp_path, sanitize=False) == []


@pytest.mark.slow
@pytest.mark.parametrize("family", [pytest.param("avr", marks=needs_simavr), pytest.param("pic16", marks=needs_gpsim)])
def test_blocks_nested_a_thousand_deep_run_on_the_part_as_simulated(family, tmp_path):
    differential = avr_differential if family == "avr" else pic16_differential
    assert differential(_on_part(family), _stimulus(40), 40, tmp_path) == []


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
