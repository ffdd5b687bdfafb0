"""`ladder build`: the summary lines (size, scan time), the HEX and listing
it writes, the target option, and located errors with exit 1."""

from __future__ import annotations

import re
import shutil

import pytest
from builders import NOT_COMPILED_LD
from intelhex import IntelHex
from test_compiler_harness import CORPUS

from ladder.cli import main
from lang.families import parts_text

SUMMARY = re.compile(r"^(ATmega\w+): flash (\d+)/(\d+) bytes \((\d+\.\d)%\), RAM (\d+)/(\d+) bytes \((\d+\.\d)%\)$")
SCAN = re.compile(r"^scan: at most ([\d,]+) cycles = ([\d.,]+) µs of the (\d+) ms cycle \((\d+\.\d)%\)")


def test_build_writes_the_hex_and_listing_beside_the_program(tmp_path, capsys):
    source = tmp_path / "traffic.ld"
    shutil.copy(CORPUS / "sample" / "traffic.ld", source)
    assert main(["build", str(source)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2
    m = SUMMARY.match(lines[0])
    assert m and m.group(1) == "ATmega128" and m.group(3) == "131072" and m.group(6) == "4096"
    scan = SCAN.match(lines[1])  # traffic.ld: 10 ms at 4 MHz, a scan of some hundred cycles
    assert scan and 50 < int(scan.group(1).replace(",", "")) < 1000 and scan.group(3) == "10"
    assert float(scan.group(2)) == pytest.approx(int(scan.group(1).replace(",", "")) / 4, rel=0.01)
    image = IntelHex(str(tmp_path / "traffic.hex"))
    assert len(image) == int(m.group(2))
    assert (tmp_path / "traffic.lst").read_text().startswith("; ATmega128")


def test_output_path_and_target(tmp_path, capsys):
    source = tmp_path / "hello.ld"
    shutil.copy(CORPUS / "sample" / "hello.ld", source)
    out = tmp_path / "out" / "firmware.hex"
    out.parent.mkdir()
    assert main(["build", str(source), "-o", str(out), "--target", "atmega328p"]) == 0
    assert SUMMARY.match(capsys.readouterr().out.splitlines()[0]).group(1) == "ATmega328P"
    assert out.exists() and out.with_suffix(".lst").exists()


def test_errors_are_located_and_exit_1(tmp_path, capsys):
    source = tmp_path / "traffic.ld"
    shutil.copy(CORPUS / "sample" / "traffic.ld", source)
    assert main(["build", str(source), "--target", "atmega328p"]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out and all(re.match(rf"^{re.escape(str(source))}:\d+:\d+: error LD\d{{3}} ", line) for line in out)
    assert out[0].startswith(f"{source}:8:1: error LD402 'Xbutton1' is assigned to pin 46")
    assert not (tmp_path / "traffic.hex").exists()


def test_no_part_is_an_error_and_a_missing_file_exits_2(tmp_path, capsys):
    source = tmp_path / "nopart.ld"
    source.write_text("LDmicro0.1\nCYCLE=10000\nCRYSTAL=4000000\n\nPROGRAM\nRUNG\n    CONTACTS Xa 0\n"
                      "    COIL Ya 0 0 0\nEND\n")
    assert main(["build", str(source)]) == 1
    assert "error LD701" in capsys.readouterr().out
    assert main(["build", str(tmp_path / "missing.ld")]) == 2


def test_an_instruction_the_family_cannot_compile_warns_in_check_and_stops_build(tmp_path, capsys):
    source = tmp_path / "segments.ld"
    source.write_text(NOT_COMPILED_LD)
    assert main(["check", str(source)]) == 0
    assert f"{source}:14:3: warning LD501 SPI 'd' in rung 1 cannot be compiled for the ATmega328P: the " \
           "AVR back end does not support it" in capsys.readouterr().out
    assert main(["build", str(source)]) == 1
    assert f"{source}:14:3: error LD501 SPI 'd' in rung 1" in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["segments.ld"]


def test_help_and_parts_name_the_compiled_parts(capsys):
    with pytest.raises(SystemExit):
        main(["build", "--help"])
    assert " ".join(parts_text().split()) in " ".join(capsys.readouterr().out.split())
    assert main(["parts"]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines()]
    assert rows[0][:4] == ["part", "package", "family", "build"]
    built = {row[0]: row[3] for row in rows[1:]}
    assert built["atmega328p"] == built["pic16f877a"] == "yes" and set(built.values()) == {"yes"}


def test_a_build_leaves_only_the_hex_and_listing(tmp_path, capsys):
    source = tmp_path / "hello.ld"
    shutil.copy(CORPUS / "sample" / "hello.ld", source)
    assert main(["build", str(source)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hello.hex", "hello.ld", "hello.lst"]
