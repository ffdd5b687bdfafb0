"""The PIC16 differential harness (pic16_harness.py) itself: a corpus program
runs scan for scan beside the simulator, with the UART's bytes both ways,
and a scan that outlasts its cycle is reported as such instead of compared
half-done."""

from __future__ import annotations

import pytest
from builders import el, program
from pic16_harness import CycleOverrun, differential
from test_compiler_harness import IN_CI, Event, load

import compiler
from compiler.run import gpsim
from compiler.run.record import record_pic16
from lang.sim import Simulator

needs_gpsim = pytest.mark.skipif(not gpsim.available() and not IN_CI, reason="gpsim not installed")


@needs_gpsim
def test_blink_follows_the_simulator(tmp_path):
    events = [Event(0, "Xbutton", 0), Event(20, "Xbutton", 1), Event(25, "Xbutton", 0), Event(60, "Xbutton", 1)]
    assert differential(load("sample/blink.ld"), events, 100, tmp_path) == []


@needs_gpsim
def test_the_bytes_received_follow_the_simulator(tmp_path):
    """sample/serial.ld at 2400 baud takes each byte into `inch` and lights
    its LED by it: the bytes come from gpsim's usart module on RC7."""
    events = [Event(100, "uart", ord("o")), Event(350, "uart", ord("x")), Event(350, "uart", ord("b"))]
    assert differential(load("sample/serial.ld"), events, 400, tmp_path) == []


@needs_gpsim
def test_the_bytes_sent_and_the_scan_each_went_out_in_follow_the_simulator(tmp_path):
    """Every write to TXREG is a byte sent: after each scan the firmware has
    sent as many bytes as the simulator."""
    program = load("sample/serial.ld")
    build = compiler.build(program)
    build.write(tmp_path / "serial.hex")
    recording = record_pic16(build, tmp_path / "serial.hex", [], 300, [])
    sim = Simulator(program)
    counts = []
    for _ in range(300):
        sim.step()
        counts.append(len(sim.uart_output()))
    assert recording.sent == sim.uart_output() == b"bc\r\nAb"
    assert recording.sent_after == counts


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
