"""The mutant suite of `ladder verify` (docs/verify.md, "The examples' properties
and their mutants"): the properties of the examples and of two corpus programs
are proved, and for each of them a fault planted in the program's model (a
contact negated or removed, a comparison removed, a timer shortened, a
counter's limit raised, a coil swapped or negated) makes `ladder verify` find a counterexample, which `ladder test` replays failing
at the scan the prover named, on the simulator and on the AVR image in simavr.
No proof without a check that it can fail.

A fault that shows only once the traffic light's 1 s clock has stepped Ccycle
to 8 or 12 would need a search of 800 to 1200 scans; such a mutant runs on a
carrier, the program with its clock's timers at 20 ms, on which the property
is first proved again: the fault, not the carrier, is what breaks it."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial as given
from pathlib import Path

import pytest
from corpus import CORPUS, EXPORTS
from mutations import drop_rung, negate_contact, remove_element, set_operand, swap_coil
from test_firmware_scenarios import needs_simavr
from test_verify import needs_z3

from ladder.cli import main
from lang.loader import load_path
from lang.model import PinAssignment, Program, PropertyLine
from lang.textform.writer import render_program

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
BOUND = "150"  # the scans searched: every mutant fails within 120 (the counter limit raised, at scan 117)

Edit = Callable[[Program], None]


@dataclass(frozen=True)
class Subject:
    """A program and the properties proved on it (for an example, its PROPERTIES section)."""

    path: Path
    properties: tuple[str, ...] = ()
    setup: tuple[Edit, ...] = ()  # what the copy a mutant is planted in needs besides the fault


def _pins_for_rung_6(program: Program) -> None:
    """demo.ld's rung 6 reads inputs and drives an output that have no pin (LD407: neither `ladder
    build` nor LDmicro builds it); free pins of the ATmega328P, which no property reads, make its
    AVR image."""
    for name, pin in {"Xa": "PD4", "Xb": "PD5", "Xc": "PD6", "Xe": "PD7", "Yout": "PB2"}.items():
        program.pins[name] = PinAssignment(name, pin)


SUBJECTS = {
    "traffic-uno": Subject(EXAMPLES / "traffic-uno.ladder"),
    "conveyor": Subject(EXAMPLES / "conveyor.ladder"),
    # its safety properties (its `within` fails and its `reachable` is reached, as docs/verify.md shows)
    "reversing-motor": Subject(EXAMPLES / "reversing-motor.ladder", (
        "never Ymotor_fwd and Ymotor_rev", "always Ylamp implies (Ymotor_fwd or Ymotor_rev)", "always Cstarts <= 100")),
    # LDmicro's own traffic light, and a motor start/stop with a start delay exported by LDmicro
    "corpus-traffic": Subject(CORPUS / "ldmicro" / "sample" / "traffic.ld", (
        "never Yred and Yyellow", "never Yred and Ygreen", "never Yyellow and Ygreen",
        "always Yred or Yyellow or Ygreen", "always Ccycle in 0..19")),
    "corpus-demo": Subject(EXPORTS / "demo.ld", (
        "always Ymotor implies Rrun", "always Rrun implies not Xstop", "always Ymotor implies Tdly >= 150",
        "Rrun within 0 ms after Xstart and not Xstop"),
        (_pins_for_rung_6,)),
}


def _properties(subject: Subject) -> tuple[str, ...]:
    if subject.properties:
        return subject.properties
    program, _ = load_path(subject.path)
    return tuple(line.text.strip() for line in program.properties if not line.text.strip().startswith("#"))


# the traffic light's clock at two scans a half period (the shortest LDmicro's timers allow);
# the conveyor's horn, the demo's start delay at 50 ms
FAST_CLOCK = (given(set_operand, name="Ton", operand="delay", value=20_000),
              given(set_operand, name="Toff", operand="delay", value=20_000))
FAST_HORN = (given(set_operand, name="Twarn", operand="delay", value=50_000),)
FAST_DELAY = (given(set_operand, name="Tdly", operand="delay", value=50_000),)


@dataclass(frozen=True)
class Mutant:
    subject: str
    property: str
    fault: str
    edits: tuple[Edit, ...]
    carrier: tuple[Edit, ...] = field(default=())


def _traffic(subject: str) -> list[Mutant]:
    return [
        Mutant(subject, "never Yred and Yyellow", "the wait lamp's coil swapped for the yellow light's",
               (given(swap_coil, coil="Ywait", other="Yyellow"),)),
        Mutant(subject, "never Yred and Ygreen", "green's [Ccycle >= 12] removed",
               (given(remove_element, coil="Ygreen", kind="GEQ", name="Ccycle"),)),
        Mutant(subject, "never Yyellow and Ygreen", "yellow's [Ccycle < 12] removed",
               (given(remove_element, coil="Yyellow", kind="LES", name="Ccycle"),), FAST_CLOCK),
        Mutant(subject, "always Yred or Yyellow or Ygreen", "the red coil negated, ( ) to (/)",
               (given(set_operand, name="Yred", operand="type", value="/"),)),
        Mutant(subject, "always Ccycle in 0..19", "the cycle counter's limit 19 raised to 20",
               (given(set_operand, name="Ccycle", operand="max", value="20"),), FAST_CLOCK),
    ]


MUTANTS = _traffic("traffic-uno") + _traffic("corpus-traffic") + [
    Mutant("traffic-uno", "always Rclock implies Toff >= 50", "the clock's TON shortened to 250 ms",
           (given(set_operand, name="Toff", operand="delay", value=250_000),)),
    Mutant("traffic-uno", "Rwait within 10 ms after not Xbutton2", "the walk button's contact negated",
           (given(negate_contact, coil="Rwait", contact="Xbutton2"),)),
    Mutant("traffic-uno", "always Ywait implies Rwait", "the wait lamp's Rwait contact negated",
           (given(negate_contact, coil="Ywait", contact="Rwait"),)),
    Mutant("traffic-uno", "never Ywait and Ygreen", "the wait lamp's [Ccycle < 8] removed",
           (given(remove_element, coil="Ywait", kind="LES", name="Ccycle"),), FAST_CLOCK),
    Mutant("conveyor", "never Ymotor and Yhorn", "the horn's interlock contact Ymotor removed",
           (given(remove_element, coil="Yhorn", kind="CONTACTS", name="Ymotor"),), FAST_HORN),
    Mutant("conveyor", "always Ymotor implies Rrun", "the motor rung's Rrun contact negated",
           (given(negate_contact, coil="Ymotor", contact="Rrun"),), FAST_HORN),
    Mutant("conveyor", "always Yhorn implies Rrun", "the horn rung's Rrun contact negated",
           (given(negate_contact, coil="Yhorn", contact="Rrun"),)),
    Mutant("conveyor", "always Rrun implies not Xstop", "the stop contact's negation lost",
           (given(negate_contact, coil="Rrun", contact="Xstop"),)),
    Mutant("conveyor", "Rrun within 0 ms after Xstart and not Xstop", "the start contact negated",
           (given(negate_contact, coil="Rrun", contact="Xstart"),)),
    Mutant("conveyor", "Yhorn within 0 ms after Rrun and not Ymotor", "the horn's interlock contact negated",
           (given(negate_contact, coil="Yhorn", contact="Ymotor"),)),
    Mutant("conveyor", "always Ymotor implies Twarn >= 200", "the horn's 2 s TON shortened to 200 ms",
           (given(set_operand, name="Twarn", operand="delay", value=200_000),)),
    Mutant("reversing-motor", "never Ymotor_fwd and Ymotor_rev", "the reverse rung's interlock contact removed",
           (given(remove_element, coil="Ymotor_rev", kind="CONTACTS", name="Ymotor_fwd"),)),
    Mutant("reversing-motor", "always Ylamp implies (Ymotor_fwd or Ymotor_rev)", "the lamp's forward contact negated",
           (given(negate_contact, coil="Ylamp", contact="Ymotor_fwd"),)),
    Mutant("reversing-motor", "always Cstarts <= 100", "the counter's start value 0 mistyped as 1000",
           (given(set_operand, name="Cstarts", operand="init", value="1000"),)),
    Mutant("corpus-demo", "always Ymotor implies Rrun", "the delay rung's Rrun contact negated",
           (given(negate_contact, coil="Ymotor", contact="Rrun"),), FAST_DELAY),
    Mutant("corpus-demo", "always Rrun implies not Xstop", "the stop contact's negation lost",
           (given(negate_contact, coil="Rrun", contact="Xstop"),)),
    Mutant("corpus-demo", "always Ymotor implies Tdly >= 150", "the 1.5 s TON shortened to 300 ms",
           (given(set_operand, name="Tdly", operand="delay", value=300_000),)),
    Mutant("corpus-demo", "Rrun within 0 ms after Xstart and not Xstop", "the seal-in's Xstart contact negated",
           (given(negate_contact, coil="Rrun", contact="Xstart"),)),
]


def _verify(capsys, path: Path, *options: str) -> tuple[int, list[str]]:
    status = main(["verify", str(path), *options])
    out, err = capsys.readouterr()
    assert not err, err
    return status, out.splitlines()


def _write(tmp_path: Path, name: str, subject: Subject, edits: tuple[Edit, ...], *properties: str) -> Path:
    """The subject's program with the edits made to its model, as a .ladder with those properties."""
    program, problems = load_path(subject.path)
    assert not [p for p in problems if p.severity == "error"], problems
    for edit in edits:
        edit(program)
    program.properties = [PropertyLine(prop) for prop in properties]
    path = tmp_path / f"{name}.ladder"
    path.write_text(render_program(program), encoding="utf-8")
    return path


def test_every_property_has_a_failing_mutant():
    for name, subject in SUBJECTS.items():
        covered = {mutant.property for mutant in MUTANTS if mutant.subject == name}
        assert covered == set(_properties(subject)), name


@needs_z3
@pytest.mark.parametrize("name", ["traffic-uno", "conveyor"])
def test_ladder_verify_proves_the_examples_properties(name, capsys):
    status, lines = _verify(capsys, SUBJECTS[name].path)
    assert status == 0
    verdicts = [line.split(": ", 1)[1] for line in lines]
    assert verdicts == [f"proved (k = 1): {prop}" for prop in _properties(SUBJECTS[name])]


@needs_z3
@pytest.mark.parametrize("name", ["reversing-motor", "corpus-traffic", "corpus-demo"])
def test_the_properties_of_the_corpus_programs_and_the_reversing_motor_are_proved(name, tmp_path, capsys):
    subject = SUBJECTS[name]
    status, lines = _verify(capsys, _write(tmp_path, name, subject, subject.setup, *subject.properties))
    assert status == 0
    assert [line.split(": ", 1)[1] for line in lines] == [f"proved (k = 1): {prop}" for prop in subject.properties]


def _mutant_id(mutant: Mutant) -> str:
    return f"{mutant.subject}: {mutant.fault}"


def _counterexample(mutant: Mutant, tmp_path: Path, capsys) -> tuple[str, Path]:
    """Verifies the mutant: the time its counterexample fails at, and its scenario file."""
    subject = SUBJECTS[mutant.subject]
    carrier = subject.setup + mutant.carrier
    if carrier:
        lines = _verify(capsys, _write(tmp_path, "carrier", subject, carrier, mutant.property), "--bound", BOUND)[1]
        assert lines[0].split(": ", 1)[1].startswith("proved"), lines
    path = _write(tmp_path, "mutant", subject, carrier + mutant.edits, mutant.property)
    status, lines = _verify(capsys, path, "--bound", BOUND)
    assert status == 1, lines
    found = re.fullmatch(r"\S+: fails at (\d+) ms \(scan \d+\): (.*)", lines[0])
    assert found and found.group(2) == mutant.property, lines
    written = re.fullmatch(r"  counterexample: (\S+\.scn) .*", lines[1])
    assert written, lines
    assert "note:" not in "\n".join(lines)  # the simulator decided it as the prover did
    return found.group(1), Path(written.group(1))


def _replay_fails_at(capsys, scenario: Path, time_ms: str, *options: str) -> None:
    status = main(["test", *options, str(scenario)])
    out = capsys.readouterr().out
    assert status == 1, out
    failures = [line for line in out.splitlines() if re.match(r"\s+\S+\.scn:\d+: at", line)]
    assert len(failures) == 1 and f": at {time_ms} ms: " in failures[0], out


@needs_z3
@pytest.mark.parametrize("mutant", MUTANTS, ids=_mutant_id)
def test_each_mutant_fails_its_property_and_ladder_test_replays_it(mutant, tmp_path, capsys):
    time_ms, scenario = _counterexample(mutant, tmp_path, capsys)
    _replay_fails_at(capsys, scenario, time_ms)


@needs_z3
@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("mutant", MUTANTS, ids=_mutant_id)
def test_each_counterexample_fails_at_the_same_scan_on_the_avr_image(mutant, tmp_path, capsys):
    time_ms, scenario = _counterexample(mutant, tmp_path, capsys)
    _replay_fails_at(capsys, scenario, time_ms, "--on", "avr")


@needs_z3
@pytest.mark.parametrize("name, coil, prop", [("conveyor", "Yhorn", "never Ymotor and Yhorn"),
                                              ("traffic-uno", "Yred", "always Yred or Yyellow or Ygreen")])
def test_a_dropped_rung_leaves_its_property_reading_a_name_nothing_drives(name, coil, prop, tmp_path, capsys):
    # a safety property holds the more surely the less a program does; what a dropped rung breaks is
    # the property itself, which must not be proved about a name the program no longer has
    path = _write(tmp_path, "dropped", SUBJECTS[name], (given(drop_rung, coil=coil),), prop)
    assert main(["verify", str(path)]) == 1
    assert f"error LD216 the property reads '{coil}', which the program does not use" in capsys.readouterr().err


@needs_z3
def test_the_forward_rungs_interlock_alone_can_go(tmp_path, capsys):
    # the reverse rung, later in the same scan, drops reverse whenever forward is on: within the
    # scan, its interlock alone keeps the two apart (the contactors still want both, and a hardware one)
    subject = SUBJECTS["reversing-motor"]
    path = _write(tmp_path, "one-interlock", subject,
                  (given(remove_element, coil="Ymotor_fwd", kind="CONTACTS", name="Ymotor_rev"),),
                  "never Ymotor_fwd and Ymotor_rev")
    assert _verify(capsys, path)[1][0].endswith(": proved (k = 1): never Ymotor_fwd and Ymotor_rev")
