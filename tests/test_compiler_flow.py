"""Program flow and the machine: jumps back within a scan, LOCK restarting
through the watchdog, SLEEP, DELAY and T2DLY timing."""

from __future__ import annotations

import re

import pytest
from test_compiler_harness import Event, differential, needs_simavr
from test_compiler_peripherals import ld

import compiler
from compiler.avr.part import Part
from compiler.run import simavr as sa

HEADER = """LDmicro0.2
MICRO=Atmel AVR ATmega328 28-PDIP
CYCLE=10000 us at Timer1, YPlcCycleDuty:0
CRYSTAL=16000000 Hz
BAUD=9600 Hz

IO LIST
    Xa at 4 0 0
    Ya at 14 0 0
    Yb at 15 0 0
END

PROGRAM
"""

LOOP = HEADER + """RUNG 1
  MOVE i 0
END
RUNG 2
  LABEL again
  PARALLEL
    ADD i i 1
    ADD total total i
  END
END
RUNG 3
  CONTACTS Xa 0 0
  LES i 5
  GOTO again
END
RUNG 4
  GRT total 100
  COIL Ya 0 0 0 0
END
"""


@needs_simavr
@pytest.mark.slow
def test_a_backward_goto_loops_within_the_scan(tmp_path):
    events = [Event(0, "Xa", 0), Event(3, "Xa", 1), Event(9, "Xa", 0)]
    assert differential(ld(LOOP), events, 30, tmp_path) == []


WATCHDOG = HEADER + """RUNG 1
  OSR
  COIL Ya 0 0 0 0
END
RUNG 2
  CONTACTS Xa 0 0
  LOCK
END
RUNG 3
  COIL Yb 0 0 0 0
END
RUNG 4
  DELAY {delay}
END
RUNG 5
  COIL Yb 0 0 1 0
END
"""


@needs_simavr
@pytest.mark.slow
def test_lock_stops_the_scan_until_the_watchdog_restarts_the_program(tmp_path):
    build = compiler.build(ld(WATCHDOG.format(delay=500)))
    build.write(tmp_path / "lock.hex")
    run = sa.simulate_avr(tmp_path / "lock.hex", build.device.part, 16_000_000, until_ms=2500,
                          inputs=[(0, "D2", 0), (95, "D2", 1), (1000, "D2", 0)], watch=["B0"])
    starts = [t for t, v in run.pin_edges_ms("B0") if v]
    # the first scan's one-shot, then again after the 2 s watchdog reset
    assert len(starts) == 2 and starts[0] < 1 and 2000 < starts[1] - 100 < 2200


@needs_simavr
@pytest.mark.slow
@pytest.mark.parametrize("delay, element", [("500", None), ("loops", "TIME2DELAY")])
def test_delay_busy_waits_the_time_asked(delay, element, tmp_path):
    text = WATCHDOG.format(delay=delay)
    if element:  # the loop count T2DLY makes for 500 us
        text = text.replace("RUNG 1\n", "RUNG 1\n  PARALLEL\n    TIME2DELAY loops 500\n    SERIES\n      OSR\n"
                                        "      COIL Ya 0 0 0 0\n    END\n  END\nEND\nRUNG 1\n  SHORT\n", 1)
    build = compiler.build(ld(text))
    build.write(tmp_path / "delay.hex")
    run = sa.simulate_avr(tmp_path / "delay.hex", build.device.part, 16_000_000, until_ms=50,
                          inputs=[(0, "D2", 0)], watch=["B1"])
    edges = run.pin_edges_ms("B1")
    widths = [fall - rise for (rise, _), (fall, _) in zip(edges[::2], edges[1::2])]
    assert len(widths) >= 4
    assert all(w == pytest.approx(0.5, abs=0.005) for w in widths[1:]), widths


def test_sleep_enters_power_down():
    """simavr ends a run when the MCU sleeps with interrupts off, so this is
    checked in the listing: the sleep mode register gets power-down and SE,
    then SLEEP (the watchdog, still running, resets the MCU)."""
    text = HEADER + "RUNG 1\n  CONTACTS Xa 0 0\n  SLEEP\nEND\n"
    build = compiler.build(ld(text))
    part = Part.of(build.device)
    sleep = part.avr["sleep"]
    listing = build.image.listing
    address = part.reg(sleep["control"])
    store = rf"(out 0x{address - 0x20:02x}|sts 0x{address:04x}), r(\d+)"
    assert re.search(store, listing) and "\tsleep" in listing
    assert f"ldi r26, 0x{sleep['power_down']:02x}" in listing
