"""`ladder build --emit c`: the files it writes, the C compilers that take
them warning-free (the host's gcc in C99 with -Wall -Wextra -Werror
-pedantic, and avr-gcc), and what it refuses."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest
from test_compiler_harness import CORPUS

from ladder.cli import main

ROOT = Path(__file__).resolve().parents[1]
WARNINGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]
# corpus programs whose every instruction C supports, of all kinds between them
PROGRAMS = [ROOT / "examples" / "conveyor.ladder"] + [CORPUS / name for name in (
    "sample/traffic.ld", "sample/7seg-display.ld", "sample/ctu_ctd_ctc_ctr.ld", "sample/var-timer.ld",
    "sample/serial.ld", "sample/frmt_escape.ld", "sample/swatch2.ld", "sample/MasterRelay-Test.ld",
    "reg/tests/integers.ld", "reg/tests/misc-ops.ld", "reg/tests/timers-counters.ld", "Tests/test-uart.ld",
    "Tests/test-adc.ld", "Tests/test-pwm.ld")]
needs_avr_gcc = pytest.mark.skipif(shutil.which("avr-gcc") is None, reason="avr-gcc not installed")


def run(capsys, *argv) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def _emit(capsys, program: Path, folder: Path) -> Path:
    source = folder / (program.stem.replace("-", "_") + program.suffix)
    shutil.copyfile(program, source)
    status, out, err = run(capsys, "build", str(source), "--emit", "c")
    assert status == 0, out + err
    return source.with_suffix(".c")


@pytest.mark.parametrize("program", PROGRAMS, ids=lambda p: p.stem)
def test_the_c_compiles_warning_free_with_gcc(program, capsys, tmp_path):
    c_file = _emit(capsys, program, tmp_path)
    done = subprocess.run(["gcc", *WARNINGS, "-c", "-o", str(tmp_path / "x.o"), str(c_file)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


@needs_avr_gcc
@pytest.mark.parametrize("program", PROGRAMS[:4] + PROGRAMS[-3:], ids=lambda p: p.stem)
def test_the_c_compiles_warning_free_with_avr_gcc(program, capsys, tmp_path):
    c_file = _emit(capsys, program, tmp_path)
    done = subprocess.run(["avr-gcc", "-mmcu=atmega328p", "-Os", *WARNINGS, "-c", "-o", str(tmp_path / "x.o"),
                           str(c_file)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def test_emit_c_writes_the_c_the_header_and_a_ladder_h_it_never_overwrites(capsys, tmp_path):
    source = tmp_path / "conveyor.ladder"
    shutil.copyfile(ROOT / "examples" / "conveyor.ladder", source)
    status, out, _ = run(capsys, "build", str(source), "--emit", "c")
    assert status == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["conveyor.c", "conveyor.h", "conveyor.ladder", "ladder.h"]
    assert "PlcCycle() is one scan, to call every 10 ms" in out
    c_text = (tmp_path / "conveyor.c").read_text()
    assert '#include "conveyor.h"' in c_text and "void PlcCycle(void)" in c_text
    assert "|-------] [---" in c_text  # each rung's drawing above its code
    header = (tmp_path / "conveyor.h").read_text()
    assert "PROTO(BOOLEAN_t Read_Ub_Xstart(void);)" in header and "PROTO(void Write_Ub_Ymotor(BOOLEAN_t v);)" in header
    (tmp_path / "ladder.h").write_text("/* mine */\n")
    # -o names a folder that does not exist yet: it is made
    status, out, _ = run(capsys, "build", str(source), "--emit", "c", "-o", str(tmp_path / "out" / "plc.c"))
    assert status == 0 and (tmp_path / "out" / "plc.h").exists() and (tmp_path / "out" / "ladder.h").exists()
    run(capsys, "build", str(source), "--emit", "c")
    assert (tmp_path / "ladder.h").read_text() == "/* mine */\n"


def test_emit_c_refuses_a_part_and_what_c_cannot_do(capsys, tmp_path):
    status, _, err = run(capsys, "build", str(ROOT / "examples" / "conveyor.ladder"), "--emit", "c",
                         "--target", "atmega8")
    assert status == 2 and "the C output (--emit c) has none" in err
    source = tmp_path / "i2c.ld"
    shutil.copyfile(CORPUS / "Tests" / "test-i2c-1.ld", source)
    status, out, _ = run(capsys, "build", str(source), "--emit", "c")
    assert status == 1
    assert "error LD501 I2C WR in rung 3 cannot be compiled for the C output" in out
    assert not source.with_suffix(".c").exists()


def test_a_subroutine_no_gosub_reaches_still_compiles(tmp_path):
    # the optimiser drops a GOSUB behind an open contact; the subroutine's return stays
    # (found by benchmarks/compiler_fuzz.py --family c: a `goto` to a dispatch never written)
    from c_harness import differential
    from test_compiler_harness import Event

    from lang.instructions import INSTRUCTIONS
    from lang.model import Element, Program, Rung, Series, Settings

    def element(kind, **args):
        return Element(kind, {**{f.name: f.default for f in INSTRUCTIONS[kind].fields}, **args})

    rungs = [Rung(Series([element("OPEN"), element("GOSUB", label="sub")])),
             Rung(Series([element("CONTACTS", name="Xa", negated=0), element("COIL", name="Ya", type=" ")])),
             Rung(Series([element("SUBPROG", label="sub")])),
             Rung(Series([element("CONTACTS", name="Xa", negated=0), element("RETURN")])),
             Rung(Series([element("COIL", name="Yb", type=" ")])),
             Rung(Series([element("ENDSUB", label="sub")]))]
    program = Program(Settings(mcu="", cycle_us=10_000), rungs)
    assert differential(program, [Event(3, "Xa", 1)], 10, tmp_path) == []


def test_a_runtime_with_ldmicros_older_spelling_links_through_one_define(capsys, tmp_path):
    c_file = _emit(capsys, ROOT / "examples" / "conveyor.ladder", tmp_path)
    done = subprocess.run(["gcc", *WARNINGS, "-DLDMICRO_OLD_NAMES", "-c", "-o", str(tmp_path / "x.o"), str(c_file)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    symbols = subprocess.run(["nm", "-u", str(tmp_path / "x.o")], capture_output=True, text=True).stdout.split()
    assert {"Read_U_b_Xstart", "Read_U_b_Xstop", "Read_U_b_Ymotor", "Write_U_b_Ymotor"} <= set(symbols)
    assert not [s for s in symbols if "_Ub_" in s]


def test_a_timer_with_no_cycle_time_is_a_located_error_not_a_crash(capsys, tmp_path):
    source = tmp_path / "nocycle.ladder"
    shutil.copyfile(ROOT / "tests" / "diagnostics" / "LD315.ladder", source)
    status, out, err = run(capsys, "build", str(source), "--emit", "c")
    assert status == 1 and "Traceback" not in err
    assert f"{source}:6:26: error LD710 Timer 'T1': the cycle time must be positive" in out + err
    assert not source.with_suffix(".c").exists()
