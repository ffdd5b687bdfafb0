"""The corpus programs that fit the PIC10F200/202 (four pins, GP3 an input
only; 255 or 511 words; 16 or 24 bytes of RAM), moved to the part as
tests/test_pic16e_ldmicro.py moves a program (a pin for each name, the
cycle-duty output on one more, the part's one clock), the cycle on Timer0
(the parts' only timer, which LDmicro requires: "Select Timer 0"), compiled and run in
gpsim against the simulator on every name after every scan
(pic16_harness.py). benchmarks/pic10_size.py compares the same programs
with LDmicro's images of them.

The corpus's other programs do not fit: more than four pins, or a UART, an
A/D converter or I2C, which the parts lack; reg/tests/integers.ld needs 24
bytes of RAM (the PIC10F202's, not the PIC10F200's 16)."""

from __future__ import annotations

from dataclasses import replace

import pytest
from pic16_harness import differential
from test_compiler_harness import Event, load
from test_pic16e_ldmicro import moved

pytestmark = pytest.mark.slow

CORPUS_PROGRAMS = [(path, part) for path in ("Tests/test-leds.ld", "sample/blink.ld", "sample/ctc_osr.ld")
                   for part in ("pic10f200", "pic10f202")] + [("reg/tests/integers.ld", "pic10f202")]
PRESSES = [Event(20, "Xbutton", 1), Event(25, "Xbutton", 0), Event(60, "Xbutton", 1), Event(62, "Xbutton", 0),
           Event(64, "Xbutton", 1), Event(66, "Xbutton", 0), Event(120, "Xbutton", 1), Event(150, "Xbutton", 0)]
RUNS = {  # stimulus, scans
    "Tests/test-leds.ld": (PRESSES, 200),
    "sample/blink.ld": (PRESSES, 200),
    "sample/ctc_osr.ld": ([], 1100),  # its TON of 1 s at a 1 ms cycle starts the counters
    "reg/tests/integers.ld": ([Event(5, "Xa", 1), Event(10, "Xa", 0), Event(15, "Xa", 1)], 30),
}


def on_pic10(path: str, part: str):
    """The corpus program moved to the part, its cycle on Timer0."""
    program = moved(load(path), part)
    assert program is not None, "too few pins"
    return replace(program, settings=replace(program.settings, cycle_timer=0))


@pytest.mark.parametrize("path, part", CORPUS_PROGRAMS)
def test_corpus_program_follows_the_simulator_on_the_part(path, part, tmp_path):
    program = on_pic10(path, part)
    events, scans = RUNS[path]
    assert differential(program, events, scans, tmp_path) == []
