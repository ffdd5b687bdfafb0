"""`ladder sim` and `ladder test`: output format, options, exit codes, and the
scenario files of tests/scenarios/ run through the command."""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

import pytest

from ladder.cli import main

SHARED = Path(__file__).resolve().parents[2] / "shared"
SAMPLES = SHARED / "corpus" / "ldmicro" / "sample"
SCENARIOS = Path(__file__).resolve().parent / "scenarios"


def run(capsys, *argv) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_sim_prints_changes_by_time_then_name(capsys):
    status, out, _ = run(capsys, "sim", str(SAMPLES / "traffic.ld"), "--for", "8s",
                         "--set", "Xbutton1=1", "--set", "Xbutton2=1")
    assert status == 0
    lines = out.splitlines()
    assert lines[:3] == ["0 Xbutton1 1", "0 Xbutton2 1", "0 Yred 1"]
    assert "490 Rclock 1" in lines and "7490 Yyellow 1" in lines
    times = [float(line.split()[0]) for line in lines]
    assert times == sorted(times)


def test_sim_set_at_a_time_and_watch(capsys, tmp_path):
    vcd = tmp_path / "out.vcd"
    status, out, _ = run(capsys, "sim", str(SAMPLES / "var-timer.ld"), "--for", "2.5s",
                         "--set", "Apot=100", "--set", "Xin=1@1s", "--watch", "Xin,Yout", "--vcd", str(vcd), "--plot")
    assert status == 0
    assert out.splitlines()[:2] == ["1000 Xin 1", "1510 Yout 1"]
    assert "time (ms)" in out and "Yout" in out.splitlines()[-1]
    text = vcd.read_text()
    assert "$var wire 1 ! Xin $end" in text and "#1000000" in text and "#1510000" in text


def test_sim_cycles_and_decimal_times(capsys):
    status, out, _ = run(capsys, "sim", str(SAMPLES / "ctu_ctd_ctc.ld"), "--cycles", "3", "--watch", "Ymeandr")
    assert status == 0 and out.splitlines() == ["0 Ymeandr 1", "1 Ymeandr 0", "2 Ymeandr 1"]


def test_sim_usage_errors_exit_2(capsys):
    assert run(capsys, "sim", str(SAMPLES / "traffic.ld"), "--for", "soon")[0] == 2
    assert run(capsys, "sim", str(SAMPLES / "traffic.ld"), "--watch", "Nothing")[0] == 2
    with pytest.raises(SystemExit) as raised:
        main(["sim", str(SAMPLES / "traffic.ld"), "--for", "1s", "--cycles", "3"])
    assert raised.value.code == 2


def test_sim_errors_are_located_and_exit_1(capsys, tmp_path):
    program = tmp_path / "div.ld"
    program.write_text("LDmicro0.2\nCYCLE=10000\n\nPROGRAM\nRUNG\n  DIV q 1 z\nEND\n", encoding="ascii")
    status, _, err = run(capsys, "sim", str(program), "--cycles", "2")
    assert status == 1 and "LD610" in err and str(program) in err
    assert "division by zero: DIV q := 1 / z with z = 0" in err


def test_a_missing_file_is_a_usage_error_in_every_command(capsys, tmp_path):
    missing = str(tmp_path / "missing.ld")
    for argv in (["check", missing], ["fmt", missing], ["sim", missing], ["build", missing], ["dump", missing],
                 ["convert", missing, str(tmp_path / "out.ladder")], ["test", str(tmp_path / "missing.scn")]):
        status, out, err = run(capsys, *argv)
        assert status == 2 and "missing" in out + err, argv


def test_scenario_files_pass(capsys, tmp_path):
    junit = tmp_path / "results.xml"
    files = sorted(str(p) for p in SCENARIOS.glob("*.scn"))
    status, out, _ = run(capsys, "test", *files, "--junit", str(junit))
    assert status == 0, out
    assert "0 failed" in out
    suites = ElementTree.parse(junit).getroot()
    assert len(suites) == len(files) and all(s.get("failures") == "0" for s in suites)


def test_failing_expectation_shows_time_signal_and_diagram(capsys, tmp_path):
    scenario = tmp_path / "wrong.scn"
    scenario.write_text(f"program {SAMPLES / 'traffic.ld'}\n"
                        "at 0 set Xbutton1 = 1, Xbutton2 = 1\n"
                        "at 1.2 s expect Ygreen = 1\n", encoding="utf-8")
    junit = tmp_path / "results.xml"
    status, out, _ = run(capsys, "test", str(scenario), "--junit", str(junit))
    assert status == 1
    assert f"{scenario}:3: at 1200 ms: Ygreen: expected Ygreen = 1, got 0" in out
    assert "time (ms)" in out and "Xbutton1" in out
    assert ElementTree.parse(junit).getroot()[0].get("failures") == "1"


def test_scenario_uart_expectations(capsys, tmp_path):
    scenario = tmp_path / "hello.scn"
    scenario.write_text(f"program {SAMPLES / 'hello.ld'}\n"
                        "at 2 s expect uart contains \"Hello, world:      1\\r\\n\"   # comment after a string\n",
                        encoding="utf-8")
    status, out, _ = run(capsys, "test", str(scenario))
    assert status == 0, out


def test_malformed_scenario_is_reported(capsys, tmp_path):
    scenario = tmp_path / "bad.scn"
    scenario.write_text(f"program {SAMPLES / 'traffic.ld'}\nsoon expect Yred = 1\n", encoding="utf-8")
    status, out, _ = run(capsys, "test", str(scenario))
    assert status == 1 and f"{scenario}:2: error" in out


def test_a_uart_expectation_with_a_number_is_reported(capsys, tmp_path):
    # the UART's output is bytes: `uart = 5` or `uart in 1..2` once crashed or misled
    for condition in ("uart = 5", "uart in 1..2"):
        scenario = tmp_path / "uart.scn"
        scenario.write_text(f"program {SAMPLES / 'hello.ld'}\nat 2 s expect {condition}\n", encoding="utf-8")
        status, out, _ = run(capsys, "test", str(scenario))
        assert status == 1 and f"{scenario}:2: error" in out and 'uart "text"' in out, out
