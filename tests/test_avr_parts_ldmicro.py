"""The later AVR parts against LDmicro 5.4.1.1's own images: a corpus program
moved to each part simavr has a core for (tests/test_avr_parts.py; traffic
and timers-counters in turn, one LDmicro build a part for the step's time
budget), written as an .ld file, compiled by LDmicro and by us, run in simavr
under the same stimulus: the same edges on every output pin, each within one
scan. And LDmicro's defect on the ATtiny85.

LDmicro is found at /opt/ldmicro/ldmicro (or LDMICRO=); these tests run in
the LDmicro step of .ci/run (marker `ldmicro`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from ldmicro_oracle import ldmicro_compile
from test_avr_parts import moved
from test_compiler_corpus import TIMERS, TRAFFIC, same_edges_as_ldmicro
from test_compiler_harness import load, needs_simavr
from test_compiler_random import NEW_AVR_BOARDS

import compiler
from lang.ldfile import write_ld

pytestmark = pytest.mark.ldmicro

PROGRAMS = {"sample/traffic.ld": (TRAFFIC, 1000), "reg/tests/timers-counters.ld": (TIMERS, 1300)}


def ldmicros_hex(program, folder: Path) -> Path:
    refused: list = []
    source = folder / "program.ld"
    source.write_bytes(write_ld(program, diagnostics=refused).replace("\n", "\r\n").encode("cp1252"))
    assert not refused, refused
    image = folder / "ldmicro.hex"
    done = ldmicro_compile(source, image)
    assert done.returncode == 0 and "Compiled okay" in done.stdout, done.stdout + done.stderr
    return image


@needs_simavr
@pytest.mark.parametrize("board, path", [(board, sorted(PROGRAMS)[i % 2]) for i, board in enumerate(NEW_AVR_BOARDS)],
                         ids=lambda x: getattr(x, "ldmicro", x))
def test_same_output_edges_as_ldmicros_hex_on_the_part(path, board, tmp_path):
    events, scans = PROGRAMS[path]
    # at 8 MHz: LDmicro clears all RAM before its first scan (the ATmega1284P's 16 KB take 14 ms at the
    # programs' 4 MHz, more than a cycle), ours only the bytes in use
    program = moved(load(path), board)
    # LDmicro's ATtiny85 cycle must be at Timer0 (ours always is): see below
    timer = 0 if board.part == "attiny85" else program.settings.cycle_timer
    program = replace(program, settings=replace(program.settings, crystal_hz=8_000_000, cycle_timer=timer))
    same_edges_as_ldmicro(program, ldmicros_hex(program, tmp_path), events, scans, tmp_path)


def test_ldmicro_refuses_the_attiny85_with_its_cycle_at_timer1(tmp_path):
    """LDmicro 5.4.1.1 programs the ATmega's 16-bit Timer1 (TCCR1B) for a
    cycle "at Timer1", its default, a register the ATtiny85 does not have
    (address 0 in its tables): every such program is refused. We build it."""
    program = moved(load("sample/traffic.ld"), next(b for b in NEW_AVR_BOARDS if b.part == "attiny85"))
    program = replace(program, settings=replace(program.settings, cycle_timer=1))
    with pytest.raises(AssertionError, match="Zero memory address not allowed"):
        ldmicros_hex(program, tmp_path)
    assert compiler.build(program).device.part == "attiny85"
