"""Fixes carried by diagnostics: the registry's `fixable` column holds, and
`ladder check --fix` makes the fixes that need no choice and writes the file."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from ladder.cli import main
from lang.checks import check_program
from lang.codes import CODES
from lang.codes_doc import fixture_of
from lang.loader import load_file

FIXTURES = Path(__file__).parent / "diagnostics"


@pytest.mark.parametrize("code", sorted(c.code for c in CODES.values() if c.rule))
def test_fixable_codes_and_only_they_carry_fixes(code):
    loaded = load_file(fixture_of(code))
    found = [d for d in loaded.diagnostics + check_program(loaded.program) if d.code == code]
    assert found, f"the fixture of {code} does not report it"
    assert all(bool(d.fixes) == CODES[code].fixable for d in found)


def test_fix_renames_a_timer_and_writes_the_file(tmp_path, capsys):
    shutil.copy(FIXTURES / "LD104.ladder", tmp_path)
    source = tmp_path / "LD104.ladder"
    assert main(["check", "--fix", str(source)]) == 0
    printed = capsys.readouterr()
    assert f"{source}: fixed: Rename 'delay' to 'Tdelay' (timer)" in printed.err
    assert printed.out == ""
    text = source.read_text(encoding="utf-8")
    assert "Tdelay" in text and " delay " not in text
    assert main(["check", str(source)]) == 0


def test_fix_leaves_a_choice_to_the_user(tmp_path, capsys):
    shutil.copy(FIXTURES / "LD103.ladder", tmp_path)
    source = tmp_path / "LD103.ladder"
    before = source.read_bytes()
    assert main(["check", "--fix", str(source)]) == 1
    assert "error LD103" in capsys.readouterr().out
    assert source.read_bytes() == before


def test_fix_on_an_ld_file_edits_it_in_place(tmp_path, capsys):
    source = tmp_path / "timer.ld"
    source.write_bytes(b"LDmicro0.2\r\nPROGRAM\r\nRUNG 1\r\n  CONTACTS Xa 0 0\r\n  TON delay 100000 0\r\n"
                       b"  COIL Ya 0 0 0 0\r\nEND\r\nRUNG 2\r\n  CONTACTS Xb 0 0\r\n  RES delay\r\nEND\r\n")
    assert main(["check", "--fix", str(source)]) == 0
    assert source.read_bytes() == (b"LDmicro0.2\r\nPROGRAM\r\nRUNG 1\r\n  CONTACTS Xa 0 0\r\n  TON Tdelay 100000 0\r\n"
                                   b"  COIL Ya 0 0 0 0\r\nEND\r\nRUNG 2\r\n  CONTACTS Xb 0 0\r\n  RES Tdelay\r\nEND\r\n")
