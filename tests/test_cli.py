"""The command line contracts of the language core: check, fmt, convert, dump,
explain, parts, new."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from corpus import CORPUS, EXPORTS

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "conveyor.ladder"
COIL_ON_INPUT = """LADDER DIAGRAM:
    ||                                    ||
    ||      Xa               Xlamp        ||
0001||-------] [-------------( )-------||
    ||                                    ||
"""


def ladder(*args, stdin: str | None = None, cwd=None):
    return subprocess.run([sys.executable, "-m", "ladder", *map(str, args)], input=stdin,
                          capture_output=True, text=True, cwd=cwd)


def test_check_a_clean_program_exits_0():
    result = ladder("check", EXAMPLE)
    assert result.returncode == 0, result.stdout + result.stderr
    assert result.stdout == ""


def test_the_examples_users_start_from_are_clean_and_formatted():
    """What a user copies first must pass `ladder check` and `ladder fmt --check` as shipped."""
    examples = sorted(EXAMPLE.parent.glob("*.ladder"))
    result = ladder("check", *examples)
    assert result.returncode == 0 and not result.stdout, result.stdout + result.stderr
    result = ladder("fmt", "--check", *examples)
    assert result.returncode == 0, result.stdout + result.stderr


def test_check_reports_path_line_col_severity_code(tmp_path):
    source = tmp_path / "lamp.ladder"
    source.write_text(COIL_ON_INPUT)
    result = ladder("check", source)
    assert result.returncode == 1
    line = next(ln for ln in result.stdout.splitlines() if " LD102 " in ln)
    assert line.startswith(f"{source}:3:")
    assert ": error LD102 " in line


def test_check_unreadable_and_missing_files_exit_2(tmp_path):
    garbage = tmp_path / "junk.ladder"
    garbage.write_bytes(bytes(range(256)))
    assert ladder("check", garbage).returncode == 2
    assert ladder("check", tmp_path / "missing.ladder").returncode == 2
    assert ladder("check").returncode == 2


def test_check_warns_once_for_a_part_without_data():
    result = ladder("check", CORPUS / "ldmicro" / "Tests" / "test-leds.ld")
    assert result.stdout.count("LD408") == 1


def test_fmt_rewrites_and_check_mode(tmp_path):
    source = tmp_path / "x.ladder"
    text = EXAMPLE.read_text()
    hand_drawn = text.replace(
        "    ||      Rrun            Ymotor                             Yhorn      ||\n"
        "0004||-------] [--------------]/[-------------------------------( )-------||",
        "\n    || Rrun  Ymotor   Yhorn\n"
        "    ||-] [---]/[----( )--").replace("0002", "0007")
    source.write_text(hand_drawn)
    assert ladder("check", source).returncode == 0
    assert ladder("fmt", "--check", source).returncode == 1
    diff = ladder("fmt", "--diff", source)
    assert diff.returncode == 0 and diff.stdout.startswith("---")
    assert ladder("fmt", source).returncode == 0
    assert ladder("fmt", "--check", source).returncode == 0


def test_fmt_stdin_to_stdout():
    result = ladder("fmt", "-", stdin=EXAMPLE.read_text())
    assert result.returncode == 0 and result.stdout == EXAMPLE.read_text()


def test_fmt_leaves_a_file_with_errors_untouched(tmp_path):
    source = tmp_path / "broken.ladder"
    broken = EXAMPLE.read_text().replace("]/[", "[?]")
    source.write_text(broken)
    result = ladder("fmt", source)
    assert result.returncode == 1 and "LD003" in result.stderr
    assert source.read_text() == broken


def test_fmt_keeps_crlf(tmp_path):
    source = tmp_path / "crlf.ladder"
    source.write_bytes(EXAMPLE.read_bytes().replace(b"\n", b"\r\n").replace(b"0002", b"0009"))
    assert ladder("fmt", source).returncode == 0
    assert b"\r\n" in source.read_bytes() and b"\n" not in source.read_bytes().replace(b"\r\n", b"")


def test_convert_both_ways_loses_nothing(tmp_path):
    original = CORPUS / "ldmicro" / "sample" / "traffic.ld"
    assert ladder("convert", original, tmp_path / "t.ladder").returncode == 0
    assert "TOF Ton: adjust -1" in (tmp_path / "t.ladder").read_text()
    assert ladder("convert", tmp_path / "t.ladder", tmp_path / "t.ld").returncode == 0
    first = json.loads(ladder("dump", original).stdout)
    second = json.loads(ladder("dump", tmp_path / "t.ld").stdout)

    def without_spans(value):
        if isinstance(value, dict):
            return {k: without_spans(v) for k, v in value.items() if k != "span"}
        if isinstance(value, list):
            return [without_spans(v) for v in value]
        return value

    assert without_spans(first) == without_spans(second)


def test_convert_writes_ldmicro_bytes(tmp_path):
    assert ladder("convert", EXAMPLE, tmp_path / "c.ld").returncode == 0
    data = (tmp_path / "c.ld").read_bytes()
    assert data.startswith(b"LDmicro0.2\r\n") and b"\r\n" in data
    assert ladder("convert", EXAMPLE, tmp_path / "c.hex").returncode == 2


def test_dump_is_versioned_json_with_stable_keys():
    first = ladder("dump", EXAMPLE).stdout
    assert first == ladder("dump", EXAMPLE).stdout
    model = json.loads(first)
    assert model["version"] == 1
    assert list(model) == ["version", "settings", "pins", "var_sizes", "pullups", "rungs"]
    assert model["settings"]["mcu"] == "Atmel AVR ATmega328 28-PDIP"


def test_explain_a_code_and_list_them():
    result = ladder("explain", "ld102")
    assert result.returncode == 0 and result.stdout.startswith("LD102:")
    listing = ladder("explain").stdout
    assert "LD004" in listing and "LD601" in listing
    assert ladder("explain", "LD999").returncode == 2


def test_parts_lists_the_parts():
    result = ladder("parts")
    assert result.returncode == 0
    for part in ("atmega328p", "atmega2560", "pic16f877a", "pic16f628a"):
        assert part in result.stdout


@pytest.mark.parametrize("part", ["atmega328p", "atmega8", "atmega2560", "pic16f877a", "pic16f628a", "pic16f88"])
def test_new_writes_a_valid_program(tmp_path, part):
    target = tmp_path / "start.ladder"
    assert ladder("new", "--part", part, target).returncode == 0
    check = ladder("check", target)
    assert check.returncode == 0, check.stdout
    assert ladder("new", "--part", part, target).returncode == 2  # will not overwrite
    assert ladder("new", "--part", "z80", tmp_path / "z.ladder").returncode == 2


def test_every_command_has_help():
    for command in ("check", "fmt", "convert", "dump", "explain", "parts", "new", "sim", "test"):
        result = ladder(command, "--help")
        assert result.returncode == 0 and "usage: ladder" in result.stdout


def test_an_export_reads_with_its_code_page(tmp_path):
    export = EXPORTS / "sample_hello.txt"
    assert ladder("check", export).returncode in (0, 1)
    result = ladder("dump", export)
    assert result.returncode == 0
