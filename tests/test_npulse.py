"""N PULSE and N PULSE OFF, as far as LDmicro 5.4.1.1 compiles them
(docs/compiler.md, "N PULSE"): it refuses every program with an N PULSE,
for every part, and compiles N PULSE OFF alone for the AVRs, where it stops
a generator that never runs. So N PULSE OFF simulates and builds for AVR
as nothing, and N PULSE stays a located LD501 in builds, LD601 in the
simulator.

The LDmicro-marked tests (the LDmicro step of .ci/run) hold both facts to
LDmicro itself: the same output edges as its HEX of an N PULSE OFF program,
and its refusals."""

from __future__ import annotations

from dataclasses import replace

import pytest
from ldmicro_oracle import ldmicro_compile
from test_avr_parts_ldmicro import ldmicros_hex
from test_compiler_corpus import same_edges_as_ldmicro
from test_compiler_harness import Event, differential, needs_simavr
from test_compiler_peripherals import ld

import compiler
from compiler.errors import CompileError
from lang.checks import check_program
from lang.diagnostics import ERROR
from lang.ldfile import write_ld
from lang.model import iter_elements
from lang.sim import SimulationError, Simulator

HEADER = """LDmicro0.2
MICRO={micro}
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Xgo at 4 0 0
    Xstop at 5 0 0
    Ypulse at 14 0 0
    Ybusy at 15 0 0
    Ystop at 16 0 0
END

PROGRAM
RUNG 1
  CONTACTS Xgo 0 0
  {rung1}
  COIL Ybusy 0 0 0 0
END
RUNG 2
  CONTACTS Xstop 0 0
  PARALLEL
    COIL Ystop 0 0 0 0
    NPULSE_OFF
  END
END
"""
ATMEGA8, ATMEGA328 = "Atmel AVR ATmega8 28-PDIP", "Atmel AVR ATmega328 28-PDIP"
PIC16F877 = "Microchip PIC16F877 40-PDIP"
STOP = HEADER.replace("  {rung1}\n", "")
GENERATE = HEADER.replace("{rung1}", "NPULSE counter 1000 Ypulse")
EVENTS = [Event(0, "Xgo", 0), Event(0, "Xstop", 0), Event(3, "Xstop", 1), Event(5, "Xgo", 1),
          Event(8, "Xstop", 0), Event(11, "Xgo", 0), Event(13, "Xstop", 1), Event(14, "Xstop", 0)]


def _outputs(text: str, events: list[Event], scans: int) -> list[tuple[int, int]]:
    sim = Simulator(ld(text))
    rows = []
    for scan in range(scans):
        for event in events:
            if event.scan == scan:
                sim.set(event.name, event.value)
        sim.step()
        rows.append((sim.value("Ybusy"), sim.value("Ystop")))
    return rows


def test_npulse_off_simulates_as_nothing():
    """A powered N PULSE OFF changes nothing: the rung's other branch and the
    rest of the program run as they would without it."""
    without = STOP.replace("  PARALLEL\n    COIL Ystop 0 0 0 0\n    NPULSE_OFF\n  END\n", "  COIL Ystop 0 0 0 0\n")
    micro = STOP.format(micro=ATMEGA8)
    assert _outputs(micro, EVENTS, 16) == _outputs(without.format(micro=ATMEGA8), EVENTS, 16)
    assert (1, 1) in _outputs(micro, EVENTS, 16)


@pytest.mark.parametrize("micro", [ATMEGA8, ATMEGA328])
def test_npulse_off_builds_for_the_avrs(micro):
    program = ld(STOP.format(micro=micro))
    assert not [d for d in check_program(program, for_build=True) if d.code == "LD501"]
    assert compiler.build(program).image.words


@pytest.mark.parametrize("micro, family", [(PIC16F877, None), (ATMEGA8, "c")])
def test_npulse_off_is_refused_where_ldmicro_refuses_it(micro, family):
    """LDmicro's PIC16 and C back ends have no code for it ("INT_2003")."""
    program = ld(STOP.format(micro=micro))
    with pytest.raises(CompileError) as refused:
        if family:
            compiler.build_c(program, "program", "program.ld")
        else:
            compiler.build(program)
    assert [d.code for d in refused.value.diagnostics] == ["LD501"]
    assert "NPULSE OFF in rung 2" in str(refused.value)


def test_npulse_is_refused_in_builds_and_in_the_simulator():
    program = ld(GENERATE.format(micro=ATMEGA328))
    errors = [d for d in check_program(program, for_build=True) if d.severity == ERROR]
    assert [d.code for d in errors] == ["LD501"] and "NPULSE 'counter' in rung 1" in errors[0].message
    npulse = next(e for e in iter_elements(program.rungs[0].circuit) if e.kind == "NPULSE")
    assert errors[0].span == npulse.span is not None
    with pytest.raises(SimulationError) as refused:
        Simulator(program)
    assert [(d.code, d.span) for d in refused.value.diagnostics] == [("LD601", npulse.span)]


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("micro", [ATMEGA8, ATMEGA328])
def test_npulse_off_matches_the_simulator_scan_for_scan(micro, tmp_path):
    assert differential(ld(STOP.format(micro=micro)), EVENTS, 16, tmp_path) == []


@pytest.mark.ldmicro
@needs_simavr
def test_npulse_off_makes_the_same_edges_as_ldmicros_hex(tmp_path):
    program = ld(STOP.format(micro=ATMEGA8))
    program = replace(program, settings=replace(program.settings, crystal_hz=8_000_000))
    same_edges_as_ldmicro(program, ldmicros_hex(program, tmp_path), EVENTS, 16, tmp_path)


def _ldmicros_refusal(text: str, tmp_path) -> str:
    source = tmp_path / "program.ld"
    source.write_bytes(write_ld(ld(text)).replace("\n", "\r\n").encode("cp1252"))
    done = ldmicro_compile(source, tmp_path / "ldmicro.hex")
    assert done.returncode == 1 and "Compiled okay" not in done.stdout
    return done.stdout + done.stderr


@pytest.mark.ldmicro
@pytest.mark.parametrize("micro", [ATMEGA8, ATMEGA328])
def test_ldmicro_refuses_every_npulse(micro, tmp_path):
    """LDmicro's AVR code for N PULSE takes its operands one place off: the
    frequency as the output pin's name, which a number is not."""
    assert "Unknown name >1000<" in _ldmicros_refusal(GENERATE.format(micro=micro), tmp_path)


@pytest.mark.ldmicro
def test_ldmicro_refuses_npulse_off_on_the_atmega328(tmp_path):
    """Its tables define neither TOIE0 nor OCIE1A for the ATmega48-328: the
    bit number -1 fails its own range check. We build it."""
    text = STOP.format(micro=ATMEGA328)
    assert "v=2147483648" in _ldmicros_refusal(text, tmp_path)
    assert compiler.build(ld(text)).device.part == "atmega328p"
