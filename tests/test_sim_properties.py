"""Any program either simulates or is refused with located diagnostics;
running it never raises anything but SimulationError (never a traceback)."""

from __future__ import annotations

from generators import programs
from hypothesis import given, settings

from lang.sim import SimulationError, Simulator


@settings(max_examples=40)
@given(programs())
def test_any_program_simulates_or_fails_cleanly(program):
    try:
        sim = Simulator(program)
    except SimulationError as problem:
        assert problem.diagnostics and all(d.code.startswith("LD6") for d in problem.diagnostics)
        return
    for _ in range(3):
        try:
            sim.step(7)
        except SimulationError as problem:
            assert problem.diagnostics[0].code.startswith("LD6") and problem.scan is not None
    simulated = sum(1 for rung in program.rungs if not rung.is_comment for _ in rung.elements())
    assert len(sim.energized()) == simulated
    sim.variables()
