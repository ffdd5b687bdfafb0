"""`ladder verify` (docs/verify.md) on small programs whose answers are known
by hand: a reversing motor's interlock, a two-hand press, a counter bounded
by a reset, an alarm latch. Each property is proved, holds up to the bound,
or fails; a counterexample is a scenario `ladder test` replays, failing at
the scan the prover named. Also: the property language's located errors,
the PROPERTIES section in the text form, and the message without z3."""

from __future__ import annotations

import re
import sys
from pathlib import Path
from xml.etree import ElementTree

import pytest
from builders import coil, contact, counter, el, par

from ladder.cli import main
from lang.model import PinAssignment, Program, PropertyLine, Rung, Series, Settings
from lang.properties import PropertyError, parse_property
from lang.sim.scenario import parse_condition
from lang.textform.reader import read_text
from lang.textform.writer import render_program

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
def _has_z3() -> bool:
    try:
        import z3  # noqa: F401
    except ImportError:
        return False
    return True


needs_z3 = pytest.mark.skipif(not _has_z3(), reason="z3-solver is not installed (pip install 'textladder[verify]')")


def _write(tmp_path: Path, name: str, rungs: list, properties: list[str]) -> Path:
    program = Program(Settings(cycle_us=10_000), [Rung(Series(items)) for items in rungs])
    for _, element in program.elements():
        for value in element.args.values():
            if isinstance(value, str) and value[:1] in "XY" and value[1:].isidentifier():
                program.pins.setdefault(value, PinAssignment(value, 0))
    program.properties = [PropertyLine(text) for text in properties]
    path = tmp_path / f"{name}.ladder"
    path.write_text(render_program(program), encoding="utf-8")
    return path


def _verify(capsys, path: Path, *options: str) -> tuple[int, list[str], str]:
    status = main(["verify", str(path), *options])
    out = capsys.readouterr()
    return status, out.out.splitlines(), out.err


def _verdicts(lines: list[str]) -> list[str]:
    """Each property's verdict, without the file and line."""
    return [line.split(": ", 1)[1] for line in lines if not line.startswith("  ")]


INTERLOCK = [
    [par([contact("Xfwd")], [contact("Yfwd")]), contact("Xstop", 1), contact("Yrev", 1), coil("Yfwd")],
    [par([contact("Xrev")], [contact("Yrev")]), contact("Xstop", 1), contact("Yfwd", 1), coil("Yrev")],
]


@needs_z3
def test_the_reversing_motor_interlock_is_proved_and_its_absence_found(tmp_path, capsys):
    path = _write(tmp_path, "motor", INTERLOCK, ["never Yfwd and Yrev"])
    status, lines, _ = _verify(capsys, path)
    assert (status, _verdicts(lines)) == (0, ["proved (k = 1): never Yfwd and Yrev"])
    # without the interlock contacts, both start together in the very first scan
    broken = [[par([contact("Xfwd")], [contact("Yfwd")]), contact("Xstop", 1), coil("Yfwd")],
              [par([contact("Xrev")], [contact("Yrev")]), contact("Xstop", 1), coil("Yrev")]]
    path = _write(tmp_path, "broken", broken, ["never Yfwd and Yrev"])
    status, lines, _ = _verify(capsys, path)
    assert status == 1 and _verdicts(lines)[0] == "fails at 0 ms (scan 1): never Yfwd and Yrev"
    assert "counterexample: " in lines[1]


@needs_z3
def test_the_two_hand_press_needs_both_hands(tmp_path, capsys):
    press = [[contact("Xleft"), contact("Xright"), contact("Xguard", 1), coil("Ypress")]]
    properties = ["always Ypress implies (Xleft and Xright)", "always Ypress implies Xleft and Xright and Xguard"]
    status, lines, _ = _verify(capsys, _write(tmp_path, "press", press, properties))
    assert status == 1
    assert _verdicts(lines) == ["proved (k = 1): always Ypress implies (Xleft and Xright)",
                                "fails at 0 ms (scan 1): always Ypress implies Xleft and Xright and Xguard"]


COUNTER = [[contact("Xpulse"), el("OSR"), el("ADD", dest="Ccount", op1="Ccount", op2="1")]]
RESET = [[el("GRT", op1="Ccount", op2="99"), el("MOVE", dest="Ccount", src="0")]]


@needs_z3
def test_a_counter_bounded_by_a_reset_is_proved_and_one_without_holds_up_to_the_bound(tmp_path, capsys):
    status, lines, _ = _verify(capsys, _write(tmp_path, "reset", COUNTER + RESET, ["always Ccount <= 100"]))
    assert (status, _verdicts(lines)) == (0, ["proved (k = 1): always Ccount <= 100"])
    # without the reset it passes 100 at the 101st rising edge: the first in scan 1, one every
    # second scan after it, so in scan 201, past a bound of 30
    path = _write(tmp_path, "free", COUNTER, ["always Ccount <= 100"])
    status, lines, _ = _verify(capsys, path, "--bound", "30")
    assert (status, _verdicts(lines)) == (0, ["holds up to 30 scans (not proved): always Ccount <= 100"])
    status, lines, _ = _verify(capsys, path, "--bound", "210")
    assert (status, _verdicts(lines)) == (1, ["fails at 2000 ms (scan 201): always Ccount <= 100"])


@needs_z3
def test_an_alarm_latch_answers_in_time_and_a_timer_does_not(tmp_path, capsys):
    latch = [[contact("Xfault"), coil("Yalarm", "S")], [contact("Xack"), contact("Xfault", 1), coil("Yalarm", "R")],
             [contact("Xfault"), el("TON", name="Tslow", delay=300_000, adjust=0), coil("Yslow")]]
    properties = ["Yalarm within 2 s after Xfault", "Yslow within 100 ms after Xfault", "reachable Yslow",
                  "reachable Yalarm and Xack"]
    status, lines, _ = _verify(capsys, _write(tmp_path, "alarm", latch, properties), "--bound", "40")
    assert status == 1
    assert _verdicts(lines) == [
        "proved (k = 1): Yalarm within 2 s after Xfault",
        "fails at 100 ms (scan 11): Yslow within 100 ms after Xfault",
        "proved: reached at 300 ms (scan 31): reachable Yslow",
        "proved: reached at 0 ms (scan 1): reachable Yalarm and Xack",
    ]


def _reported(lines: list[str]) -> list[tuple[str, str, Path]]:
    """(verdict, time in ms, scenario file) of each counterexample or witness."""
    found = []
    for verdict, note in zip(lines, lines[1:]):
        written = re.search(r"(?:counterexample|witness): (\S+\.scn)", note)
        when = re.search(r"at (\d+) ms", verdict)
        if written and when:
            found.append((verdict, when.group(1), Path(written.group(1))))
    return found


@needs_z3
def test_each_counterexample_replays_in_ladder_test_failing_at_the_same_scan(tmp_path, capsys):
    program = INTERLOCK + [[contact("Yfwd"), el("TON", name="Trun", delay=50_000, adjust=0), coil("Yrunning")],
                           [contact("Yfwd"), counter("CTU", "Cstarts", 3)]]
    properties = ["never Yfwd and Xrev", "always Cstarts < 2", "Yrunning within 30 ms after Yfwd",
                  "never Yrunning and not Yfwd", "reachable Cstarts = 2"]
    status, lines, _ = _verify(capsys, _write(tmp_path, "replay", program, properties), "--bound", "20")
    assert status == 1
    reported = _reported(lines)
    assert len(reported) == 4  # three failures and a witness; the last `never` is proved
    for verdict, time_ms, scenario in reported:
        assert scenario.exists() and scenario.with_suffix(".vcd").exists()
        status = main(["test", str(scenario)])
        out = capsys.readouterr().out
        if "reachable" in verdict:
            assert status == 0 and out.startswith("ok "), out
            continue
        assert status == 1, out
        failures = [line for line in out.splitlines() if re.match(r"  \S+\.scn:\d+: at", line)]
        assert len(failures) == 1 and f": at {time_ms} ms: " in failures[0], (verdict, out)
    assert "note:" not in "\n".join(lines)


@needs_z3
def test_properties_in_a_scenario_file(tmp_path, capsys):
    path = _write(tmp_path, "motor", INTERLOCK, [])
    scenario = tmp_path / "motor.scn"
    scenario.write_text("program motor.ladder\nproperty never Yfwd and Yrev\n"
                        "scenario forward\nat 0 set Xfwd = 1\nat 10 ms expect Yfwd\n"
                        "property   always Yrev implies   Xstopp\n", encoding="utf-8")
    status, lines, err = _verify(capsys, scenario)
    assert status == 1 and f"{scenario}:6:34: error LD216 the property reads 'Xstopp'" in err
    scenario.write_text(scenario.read_text(encoding="utf-8").replace("Xstopp", "not Yfwd"), encoding="utf-8")
    status, lines, _ = _verify(capsys, scenario)
    assert status == 0 and lines == [f"{scenario}:2: proved (k = 1): never Yfwd and Yrev",
                                     f"{scenario}:6: proved (k = 1): always Yrev implies   not Yfwd"]
    # ladder test runs the scenario and leaves the properties to ladder verify
    assert main(["test", str(scenario)]) == 0
    assert path.exists()


def test_a_scenario_files_program_with_errors_is_refused_as_a_program_file_is(tmp_path, capsys):
    """No proof about a program that would not be built: its checks' errors, whichever file
    names the properties."""
    broken = [[contact("Xfwd"), coil("Xstop")]]  # a coil on an input: LD102
    path = _write(tmp_path, "broken", broken, ["never Xstop and Xfwd"])
    scenario = tmp_path / "broken.scn"
    scenario.write_text("program broken.ladder\nproperty never Xstop and Xfwd\n", encoding="utf-8")
    for verified in (path, scenario):
        status, lines, err = _verify(capsys, verified)
        assert status == 1 and lines == [] and re.search(rf"{re.escape(str(path))}:\d+:\d+: error LD102 ", err), err


@needs_z3
def test_what_the_prover_does_not_model_is_a_located_error(tmp_path, capsys):
    loop = [[el("LABEL", label="again"), contact("Xgo"), coil("Yon")], [contact("Xloop"), el("GOTO", label="again")]]
    status, _, err = _verify(capsys, _write(tmp_path, "loop", loop, ["always Yon implies Xgo"]))
    assert status == 2 and re.search(r"loop\.ladder:\d+:\d+: error LD620 a GOTO back to an earlier rung", err)


def test_without_the_solver_one_message_names_the_pip_command(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "z3", None)  # `import z3` raises ImportError
    status, lines, err = _verify(capsys, _write(tmp_path, "motor", INTERLOCK, ["never Yfwd and Yrev"]))
    assert (status, lines) == (2, [])
    assert err == ("ladder verify: error: the SMT solver z3 is not installed; install it with: "
                   "pip install 'textladder[verify]'\n")


def test_malformed_properties_are_located_errors(tmp_path, capsys):
    path = _write(tmp_path, "motor", INTERLOCK, ["never Yfwd and", "Yfwd within 2 weeks after Xfwd",
                                                "eventually Yfwd", "always Ynone"])
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert [line.split(": ", 1)[1] for line in out] == [
        "error LD215 cannot read the condition 'Yfwd and': expected a name, at the end of 'Yfwd and'",
        "error LD215 bad time '2 weeks' (write e.g. 500 ms, 1.2 s)",
        "error LD215 cannot read the property: write `always COND`, `never COND`, `reachable COND` or "
        "`COND within TIME after COND`",
        "error LD216 the property reads 'Ynone', which the program does not use",
    ]
    status, _, err = _verify(capsys, path)
    assert status == 1 and err.count(" error LD215 ") == 3


@pytest.mark.parametrize("text, message, columns", [
    ("always (Xa", "expected `)`", (13, 14)),
    ("never Xa and or Xb", "expected a name, not 'or'", (16, 18)),
    ("Ya within 1 s after", "cannot read the property", (3, 22)),
    ("reachable", "`reachable` needs a condition", (3, 12)),
    ("always Cx in 5", "expected `..` between the bounds", (17, 18)),
    ("always Xa = 'ab'", "expected one character", (15, 19)),
])
def test_property_errors_name_the_place(text, message, columns):
    with pytest.raises(PropertyError) as raised:
        parse_property("  " + text, 7)
    span = raised.value.span
    assert message in str(raised.value) and (span.line, span.col + 1, span.end_col + 1) == (7, *columns)


def test_conditions_print_as_they_read_and_evaluate_on_values():
    values = {"Xa": 1, "Xb": 0, "Cn": 7, "Cm": 7}
    for text, printed, holds in [
        ("Xa and not Xb or Cn > 10", "(Xa and not Xb) or Cn > 10", True),
        ("Xa and (Xb or Cn = Cm)", "Xa and (Xb or Cn = Cm)", True),
        ("Xb implies Xa implies Cn in 0..5", "Xb implies (Xa implies Cn in 0..5)", True),
        ("not (Xa implies Xb)", "not (Xa implies Xb)", True),
        ("Cn != Cm or Xb", "Cn != Cm or Xb", False),
    ]:
        condition = parse_condition(text)
        assert (str(condition), condition.evaluate(values.__getitem__)) == (printed, holds)
        assert parse_condition(printed) == condition


def test_the_properties_section_is_kept_as_written_through_the_formatter():
    text = (EXAMPLES / "reversing-motor.ladder").read_text(encoding="utf-8")
    program, problems = read_text(text)
    assert problems == [] and render_program(program) == text
    assert [line.text.strip() for line in program.properties][0] == "never Ymotor_fwd and Ymotor_rev"


def test_scenario_expectations_take_conditions(tmp_path, capsys):
    path = _write(tmp_path, "motor", INTERLOCK, [])
    scenario = tmp_path / "both.scn"
    scenario.write_text("program motor.ladder\nat 0 set Xfwd = 1, Xrev = 1\n"
                        "from 0 to 30 ms expect not (Yfwd and Yrev)\nat 20 ms expect Yfwd and not Yrev\n"
                        "at 30 ms expect Yrev or Xstop\n", encoding="utf-8")
    assert main(["test", str(scenario)]) == 1
    out = capsys.readouterr().out
    assert f"{scenario}:5: at 30 ms: Yrev, Xstop: expected Yrev or Xstop, got Yrev = 0, Xstop = 0" in out
    assert len(re.findall(rf"{re.escape(str(scenario))}:\d+:", out)) == 1 and path.exists()


@needs_z3
def test_bytes_received_on_the_uart_are_inputs_and_a_counterexample_sends_them(tmp_path, capsys):
    # a byte taken when Xgo asks for one; 'A' then lights Ygot; a send keeps the transmitter busy
    uart = [[contact("Xgo"), el("UART_RECV", var="vin", bytes=1, wait=0)],
            [el("EQU", op1="vin", op2="'A'"), coil("Ygot", "S")],
            [contact("Xsend"), el("UART_SEND", var="vin", bytes=1, wait=0), coil("Ybusy")]]
    properties = ["never Ygot", "reachable Ygot and Ybusy", "always Ybusy implies Xsend"]
    status, lines, _ = _verify(capsys, _write(tmp_path, "uart", uart, properties), "--bound", "10")
    assert status == 1
    assert _verdicts(lines) == ["fails at 0 ms (scan 1): never Ygot", "proved: reached at 0 ms (scan 1): "
                                "reachable Ygot and Ybusy", "proved (k = 1): always Ybusy implies Xsend"]
    for verdict, _, scenario in _reported(lines):
        assert 'uart "A' in scenario.read_text(encoding="utf-8")  # then any bytes left untaken
        status = main(["test", str(scenario)])
        out = capsys.readouterr().out
        assert status == (0 if "reachable" in verdict else 1), out
        assert "reachable" in verdict or f"{scenario}:" in out and ": at 0 ms: " in out
    assert "note:" not in "\n".join(lines)


@needs_z3
def test_junit_has_a_case_per_property_and_out_chooses_the_folder(tmp_path, capsys):
    press = [[contact("Xleft"), contact("Xright"), coil("Ypress")]]
    path = _write(tmp_path, "press", press, ["always Ypress implies Xleft", "never Ypress and not Xright",
                                             "always Ypress implies not Xleft"])
    junit, out = tmp_path / "results.xml", tmp_path / "cex"
    status, lines, _ = _verify(capsys, path, "--junit", str(junit), "--out", str(out))
    assert status == 1 and (out / "press-property3.scn").exists() and (out / "press-property3.vcd").exists()
    root = ElementTree.parse(junit).getroot()
    cases = root.findall("./testsuite/testcase")
    assert [case.get("name") for case in cases] == ["always Ypress implies Xleft", "never Ypress and not Xright",
                                                    "always Ypress implies not Xleft"]
    assert [case.find("failure") is not None for case in cases] == [False, False, True]
    # the scenario names the program from where it is written
    assert "program ../press.ladder" in (out / "press-property3.scn").read_text(encoding="utf-8")


@needs_z3
def test_the_time_allowed_stops_the_search_with_what_was_searched(tmp_path, capsys):
    status, lines, _ = _verify(capsys, _write(tmp_path, "slow", COUNTER, ["always Ccount <= 100"]),
                               "--bound", "100000", "--timeout", "0.5")
    assert status == 0
    assert re.fullmatch(r"holds up to \d+ scans \(not proved\); the time allowed ran out: always Ccount <= 100",
                        _verdicts(lines)[0])
