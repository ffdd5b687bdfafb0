"""`ladder test --on avr|pic16|c`: the repository's scenario files pass on the
compiled program of every program whose part the runner supports (the AVR
HEX in simavr, the PIC16 HEX in gpsim, the C on the host), a wrong image
fails with the place it parts from the simulator, and what a firmware cannot
be given or a tool that is missing is a clear message."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_compiler_harness import IN_CI

import compiler
from compiler.run import c as c_run
from compiler.run import gpsim
from compiler.run import simavr as sa
from ladder.cli import main
from lang.loader import load_path
from lang.sim.scenario import parse_scenarios

SCENARIOS = Path(__file__).resolve().parent / "scenarios"
needs_cc = pytest.mark.skipif(not c_run.available(), reason="no C compiler (Debian: gcc)")
needs_simavr = pytest.mark.skipif(not sa.available() and not IN_CI, reason="gcc + libsimavr-dev not installed")
needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


def _family(scenario_file: Path) -> str | None:
    from lang.devices import find_device

    program_path = parse_scenarios(scenario_file.read_text(), str(scenario_file))[0].program
    program, _ = load_path(program_path)
    device = find_device(program.settings.mcu) if program.settings.mcu else None
    return device.family if device is not None else None


FILES = sorted(SCENARIOS.glob("*.scn"))


def run(capsys, *argv) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


@needs_cc
def test_every_scenario_passes_on_the_c(capsys):
    status, out, _ = run(capsys, "test", "--on", "c", *map(str, FILES))
    assert status == 0, out
    assert " 0 failed" in out


@pytest.mark.slow
@pytest.mark.parametrize("family", [pytest.param("avr", marks=needs_simavr), pytest.param("pic16", marks=needs_gpsim)])
def test_each_familys_scenarios_pass_on_its_hex(family, capsys):
    files = [str(f) for f in FILES if _family(f) == family]
    assert len(files) >= 2
    status, out, _ = run(capsys, "test", "--on", family, *files)
    assert status == 0, out


@needs_simavr
@pytest.mark.slow
def test_a_wrong_hex_fails_where_it_parts_from_the_simulator(capsys, monkeypatch):
    # the image of a traffic light whose clock runs twice as fast as the program says
    build = compiler.build

    def wrong(program, target=None, severities=None):
        for _, element in program.elements():
            if element.kind in ("TON", "TOF"):
                element.args["delay"] = element.args["delay"] // 2
        return build(program, target)

    monkeypatch.setattr(compiler, "build", wrong)
    status, out, _ = run(capsys, "test", "--on", "avr", str(SCENARIOS / "traffic.scn"))
    assert status == 1
    assert "FAIL" in out and "on the AVR image in simavr; the simulator passes this check" in out
    assert "traffic.scn:10: at " in out  # the first expectation it breaks, with its line and time


def test_what_a_firmware_cannot_be_given_is_a_located_failure(capsys, tmp_path):
    scenario = tmp_path / "relay.scn"
    scenario.write_text(f"program {SCENARIOS.parent / 'pic16_programs' / 'p16f877_timers.ld'}\n"
                        "scenario set a timer\nat 0 set Ton = 3\nat 10 ms expect Yton = 0\n")
    status, out, _ = run(capsys, "test", "--on", "pic16", str(scenario))
    assert status == 1
    assert "relay.scn:3: at 0 ms: Ton: cannot set Ton on the PIC16 image in gpsim: only inputs and A/D readings" \
        in out
    assert "relay.scn:4: at 10 ms: Yton: not checked (Yton = 0): the run on the PIC16 image in gpsim stops before " \
           "the scan at 0 ms, where line 3 cannot be given to it" in out


@needs_gpsim
@pytest.mark.slow
def test_expectations_before_what_a_firmware_cannot_be_given_are_checked(capsys, tmp_path):
    scenario = tmp_path / "late.scn"
    scenario.write_text(f"program {SCENARIOS.parent / 'pic16_programs' / 'p16f877_timers.ld'}\n"
                        "scenario a timer set late\n"
                        "at 0 set Xa = 0, Xb = 0, Xres = 0\n"
                        "at 100 ms set Xa = 1\n"
                        "from 100 ms to 140 ms expect Yton = 1\n"
                        "at 120 ms set Ton = 3\n"
                        "at 110 ms expect Yton = 0\n"
                        "at 200 ms expect Yton = 1\n")
    status, out, _ = run(capsys, "test", "--on", "pic16", str(scenario))
    assert status == 1
    lines = [line.strip()[len(str(scenario)) + 1:] for line in out.splitlines()
             if line.strip().startswith(f"{scenario}:")]
    assert lines == [
        "5: at 100 ms: Yton: expected Yton = 1, got 0",
        "6: at 120 ms: Ton: cannot set Ton on the PIC16 image in gpsim: only inputs and A/D readings come from "
        "outside the MCU",
        "8: at 200 ms: Yton: not checked (Yton = 1): the run on the PIC16 image in gpsim stops before the scan "
        "at 120 ms, where line 6 cannot be given to it"], out


def test_a_missing_simulator_names_its_debian_package(capsys, monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    status, _, err = run(capsys, "test", "--on", "pic16", str(FILES[0]))
    assert status == 2
    assert "--on pic16: gpsim is not installed (Debian package: gpsim)" in err
