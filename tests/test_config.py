"""A project's severities: found upward from the program, applied by `ladder
check`, never lowering an error in `ladder build`, refused when wrong."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from ladder.cli import main
from lang import config
from lang.diagnostics import Diagnostic

FIXTURES = Path(__file__).parent / "diagnostics"


def _project(tmp_path: Path, table: str, *fixtures: str, name: str = "pyproject.toml") -> Path:
    (tmp_path / name).write_text(table, encoding="utf-8")
    folder = tmp_path / "src" / "plc"
    folder.mkdir(parents=True)
    for fixture in fixtures:
        shutil.copy(FIXTURES / fixture, folder)
    return folder


def _run(capsys, *argv) -> tuple[int, str, str]:
    status = main([str(a) for a in argv])
    printed = capsys.readouterr()
    return status, printed.out, printed.err


def test_a_warning_turned_off_and_one_made_an_error(tmp_path, capsys):
    folder = _project(tmp_path, '[tool.ladder.diagnostics]\nLD131 = "off"\nld323 = "error"\n',
                      "LD131.ladder", "LD323.ladder")
    status, out, _ = _run(capsys, "check", folder / "LD131.ladder", folder / "LD323.ladder")
    assert "LD131" not in out
    assert " error LD323 " in out and status == 1


def test_ladder_toml_and_the_nearest_file_win(tmp_path, capsys):
    folder = _project(tmp_path, '[tool.ladder.diagnostics]\nLD131 = "error"\n', "LD131.ladder")
    (folder / "ladder.toml").write_text('[diagnostics]\nLD131 = "off"\n', encoding="utf-8")
    assert _run(capsys, "check", folder / "LD131.ladder")[:2] == (0, "")


def test_a_pyproject_without_the_table_is_passed_over(tmp_path, capsys):
    folder = _project(tmp_path, '[diagnostics]\nLD131 = "off"\n', "LD131.ladder", name="ladder.toml")
    (folder / "pyproject.toml").write_text('[project]\nname = "plc"\n', encoding="utf-8")
    assert _run(capsys, "check", folder / "LD131.ladder")[:2] == (0, "")


def test_a_build_never_lowers_an_error_but_may_raise_a_warning(tmp_path, capsys):
    folder = _project(tmp_path, '[tool.ladder.diagnostics]\nLD709 = "error"\nLD322 = "off"\n', "LD709.ladder")
    status, out, _ = _run(capsys, "build", folder / "LD709.ladder")
    assert status == 1 and " error LD709 " in out
    assert not (folder / "LD709.hex").exists()
    error = Diagnostic("LD322", "error", "inserts a variable but names none", None)
    settings = config.parse({"LD322": "off"}, "test")
    assert settings.apply([error]) == []
    assert settings.apply([error], building=True) == [error]


@pytest.mark.parametrize("table, says", [
    ('LD999 = "off"', "LD999: no such diagnostic code"),
    ('LD003 = "off"', "reading errors (LD0xx) and simulation faults (LD6xx) keep their severity"),
    ('LD131 = "hint"', 'expected "error", "warning", "info" or "off"'),
    ('LD131 = ', "cannot read"),
])
def test_a_wrong_setting_is_a_usage_error_naming_the_file(tmp_path, capsys, table, says):
    folder = _project(tmp_path, f"[tool.ladder.diagnostics]\n{table}\n", "LD131.ladder")
    status, _, err = _run(capsys, "check", folder / "LD131.ladder")
    assert status == 2 and says in err and "pyproject.toml" in err
