"""The corpus programs that fit the PIC10F200/202 (four pins, GP3 an input
only; 255 or 511 words; 16 or 24 bytes of RAM), moved to the part as
tests/test_pic16e_ldmicro.py moves a program (a pin for each name, the
cycle-duty output on one more, the part's one clock), the cycle on Timer0
(the parts' only timer, which LDmicro requires: "Select Timer 0"), compiled and run in
gpsim against the simulator on every name after every scan
(pic16_harness.py). benchmarks/pic10_size.py compares the same programs
with LDmicro's images of them.

Three more are cut down to the part's pins (CUT_DOWN): the outputs that find
no pin (after the inputs, GP3 first, and the cycle-duty output) become
internal relays, so every rung is compiled and compared as written, and
only the pins they drove are gone. The corpus's other programs do not fit:
more inputs than the part has pins (reg/tests/contacts.ld), names without a
pin, or a UART, an A/D converter, I2C or SPI, which the parts lack;
reg/tests/integers.ld needs 24 bytes of RAM (the PIC10F202's, not the
PIC10F200's 16)."""

from __future__ import annotations

import re
from dataclasses import replace

import pytest
from pic16_harness import differential
from test_compiler_harness import CORPUS, Event, load
from test_pic16e_ldmicro import moved

from lang.loader import parse

pytestmark = pytest.mark.slow

OUTPUT_PINS = 3  # GP0, GP1, GP2: the inputs past GP3's one, the outputs and the cycle-duty output share them
CUT_DOWN = ("reg/tests/timers-counters.ld", "sample/traffic.ld", "sample/ctu_ctd_ctc.ld")
CORPUS_PROGRAMS = [(path, part) for path in ("Tests/test-leds.ld", "sample/blink.ld", "sample/ctc_osr.ld", *CUT_DOWN)
                   for part in ("pic10f200", "pic10f202")] + [("reg/tests/integers.ld", "pic10f202")]
PRESSES = [Event(20, "Xbutton", 1), Event(25, "Xbutton", 0), Event(60, "Xbutton", 1), Event(62, "Xbutton", 0),
           Event(64, "Xbutton", 1), Event(66, "Xbutton", 0), Event(120, "Xbutton", 1), Event(150, "Xbutton", 0)]
RUNS = {  # stimulus, scans
    "Tests/test-leds.ld": (PRESSES, 200),
    "sample/blink.ld": (PRESSES, 200),
    "sample/ctc_osr.ld": ([], 1100),  # its TON of 1 s at a 1 ms cycle starts the counters
    "reg/tests/integers.ld": ([Event(5, "Xa", 1), Event(10, "Xa", 0), Event(15, "Xa", 1)], 30),
    "reg/tests/timers-counters.ld": ([Event(s, name, v) for s, name, v in (
        (50, "Xup", 1), (900, "Xup", 0), (950, "Xdown", 1), (1300, "Xdown", 0), (1320, "Xres", 1),
        (1325, "Xres", 0))], 1400),
    # the buttons read pressed when low; the lights change every 0.5 s, green after 12 s
    "sample/traffic.ld": ([Event(0, "Xbutton1", 1), Event(0, "Xbutton2", 1), Event(300, "Xbutton2", 0),
                           Event(310, "Xbutton2", 1), Event(1500, "Xbutton1", 0), Event(1510, "Xbutton1", 1)],
                          2600),
    "sample/ctu_ctd_ctc.ld": ([], 1500),
}


def as_relays(text: str, names: list[str]) -> str:
    """The .ld text with the named outputs made internal relays (out of the I/O list, Y... read R...)."""
    for name in names:
        text = re.sub(rf"\n\s+{name} at [^\n]*", "", text)
        text = re.sub(rf"\b{name}\b", f"R{name[1:]}", text)
    return text


def cut_down(path: str):
    """The corpus program with the outputs that find no pin on a PIC10F20x made internal relays."""
    text = (CORPUS / path).read_text()
    io = re.findall(r"\n\s+([XY]\w*) at ", text)
    inputs, outputs = [n for n in io if n[0] == "X"], [n for n in io if n[0] == "Y"]
    room = OUTPUT_PINS - max(0, len(inputs) - 1) - 1
    program, _ = parse(as_relays(text, outputs[room:]), "ld")
    return program


def on_pic10(path: str, part: str):
    """The corpus program (cut down to the part's pins when it is one of
    CUT_DOWN) moved to the part, its cycle on Timer0."""
    program = moved(cut_down(path) if path in CUT_DOWN else load(path), part)
    assert program is not None, "too few pins"
    return replace(program, settings=replace(program.settings, cycle_timer=0))


@pytest.mark.parametrize("path, part", CORPUS_PROGRAMS)
def test_corpus_program_follows_the_simulator_on_the_part(path, part, tmp_path):
    program = on_pic10(path, part)
    events, scans = RUNS[path]
    assert differential(program, events, scans, tmp_path) == []
