"""Helpers for simulator tests (driving an input scan by scan), and the
simulator API's basic contract. Programs are built with tests/builders.py."""

from __future__ import annotations

import pytest
from builders import coil, contact, el, program
from builders import par as parallel
from builders import ser as series

from lang.model import Element
from lang.sim import ElementKey, SimulationError, Simulator


def drive(sim: Simulator, name: str, pattern: str, watch: str) -> str:
    """Set input `name` to each character of `pattern` before a scan and
    return `watch` after each scan, as a string of 0/1 (or values)."""
    out = []
    for level in pattern:
        sim.set_input(name, int(level))
        sim.step()
        out.append(str(sim.value(watch)))
    return "".join(out)


def through(*middle: Element, cycle_us: int = 10000, **kwargs) -> Simulator:
    """Xin -> middle elements -> Yout."""
    return Simulator(program([contact("Xin"), *middle, coil("Yout")], cycle_us=cycle_us, **kwargs))


# --- the API ---------------------------------------------------------------------


def test_time_and_scan_count():
    sim = through()
    assert sim.time_ms == 0 and sim.scan_count == 0
    sim.step(3)
    assert sim.scan_count == 3 and sim.time_ms == 30
    sim.run_for(25)  # scans at 30, 40, 50 ms
    assert sim.scan_count == 6


def test_run_for_counts_scans_in_the_interval():
    sim = through(cycle_us=3000)
    sim.run_for(10)  # 0, 3, 6, 9
    assert sim.scan_count == 4


def test_inputs_values_and_variables():
    sim = Simulator(program([contact("Xa"), el("MOVE", dest="v", src="300")]))
    sim.set_input("Xa", 1)
    sim.step()
    assert sim.value("v") == 300
    assert sim.variables() == {"Xa": 1, "v": 300}
    sim.set_variable("v", 70000)  # wraps to 2 bytes
    assert sim.value("v") == 70000 - 65536
    with pytest.raises(KeyError):
        sim.value("nothing")
    with pytest.raises(KeyError):
        sim.set_input("v", 1)


def test_energized_per_element_of_the_last_scan():
    sim = Simulator(program([contact("Xa"), parallel(coil("Y1"), series(contact("Xb"), coil("Y2")))]))
    sim.set_input("Xa", 1)
    sim.step(5)
    assert sim.energized() == {ElementKey(0, 0): True, ElementKey(0, 1): True,
                               ElementKey(0, 2): False, ElementKey(0, 3): False}


def test_reload_keeps_names_that_still_exist():
    first = program([contact("Xa"), el("CTU", name="Cn", max="100", init="0", kind="-")])
    sim = Simulator(first)
    sim.set_input("Xa", 1)
    sim.step(7)
    second = program([contact("Xa"), el("CTU", name="Cn", max="100", init="0", kind="-"), coil("Ynew")])
    sim.reload(second)
    assert sim.value("Cn") == 7 and sim.value("Xa") == 1 and sim.scan_count == 7
    sim.step()
    assert sim.value("Cn") == 8


def test_reset_starts_over():
    sim = through(el("TON", name="Tt", delay=30000, adjust=0))
    sim.set_input("Xin", 1)
    sim.step(10)
    sim.reset()
    assert sim.scan_count == 0 and sim.value("Tt") == 0 and sim.value("Xin") == 0


def test_unsupported_instruction_is_a_located_error():
    sleepy = el("SLEEP", name="", delay="")
    with pytest.raises(SimulationError) as raised:
        Simulator(program([contact("Xa"), sleepy]))
    diagnostic = raised.value.diagnostics[0]
    assert diagnostic.code == "LD601" and "SLEEP" in diagnostic.message
