"""The PIC16 differential harness (pic16_harness.py) itself: a corpus program
runs scan for scan beside the simulator, and a scan that outlasts its cycle
is reported as such instead of compared half-done."""

from __future__ import annotations

import pytest
from builders import el, program
from pic16_harness import CycleOverrun, differential
from test_compiler_harness import IN_CI, Event, load

from compiler.run import gpsim

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


@needs_gpsim
def test_blink_follows_the_simulator(tmp_path):
    events = [Event(0, "Xbutton", 0), Event(20, "Xbutton", 1), Event(25, "Xbutton", 0), Event(60, "Xbutton", 1)]
    assert differential(load("sample/blink.ld"), events, 100, tmp_path) == []


@needs_gpsim
def test_a_scan_longer_than_the_cycle_is_an_overrun(tmp_path):
    """Seven 32-bit multiplications and divisions take more than the 9,000
    instruction cycles 0.9 of a 10 ms cycle has at 4 MHz."""
    points = ("-18", "25"), ("-5", "-16"), ("14", "6"), ("19", "4"), ("23", "-2")
    slow = program([el("PIECEWISE_LINEAR", dest="vr", index="va", points=points)],
                   [el("PIECEWISE_LINEAR", dest="vr", index="vb", points=points)],
                   mcu="Microchip PIC16F876 28-PDIP or 28-SOIC", crystal_hz=4_000_000,
                   sizes={"va": 2, "vb": 1, "vr": 4})
    with pytest.raises(CycleOverrun, match="scan 0 still running"):
        differential(slow, [], 5, tmp_path)
    slow.settings.crystal_hz = 20_000_000
    assert differential(slow, [], 5, tmp_path) == []
