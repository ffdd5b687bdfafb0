"""A large program is compiled in chunks (lang/sim/compile.py): it must
simulate exactly as the same program compiled as one function, with jumps,
subroutine returns, the master relay and faults across chunk boundaries."""

from __future__ import annotations

from unittest import mock

from builders import coil, contact, el, program, timer
from builders import par as parallel
from generators import programs
from hypothesis import given, settings

import lang.sim.compile as chunking
from lang.sim import SimulationError, Simulator

ONE_FUNCTION = {"SINGLE_ELEMENTS": 10**9}
AS_SHIPPED = {"SINGLE_ELEMENTS": chunking.SINGLE_ELEMENTS}
EVERY_RUNG_A_CHUNK = {"SINGLE_ELEMENTS": 0, "CHUNK_LINES": 1}


def observe(prog, steps, **constants) -> list:
    """Compiled with these chunking constants, what the simulator shows
    after each (inputs, scans) step: faults, values, powered elements."""
    with mock.patch.multiple(chunking, **constants):
        try:
            sim = Simulator(prog)
        except SimulationError as refused:
            return [d.message for d in refused.diagnostics]
    seen = []
    for inputs, scans in steps:
        for name, value in inputs.items():
            sim.set_input(name, value)
        try:
            sim.step(scans)
        except SimulationError as fault:
            seen.append([d.message for d in fault.diagnostics])
        seen.append((sim.variables(), sim.energized(), sim.scan_count))
    return seen


def jumping_program(chain: int = 0):
    """GOTO forwards and backwards, a GOSUB returning mid-rung, a master
    relay zone, then `chain` timer rungs."""
    return program(
        [contact("Xskip"), el("GOTO", label="loop")],
        [contact("Xa"), parallel([el("GOSUB", label="twice"), coil("Ycalled")], coil("Ybranch")), coil("Yafter")],
        [contact("Xzone"), el("MASTER_RELAY")],
        [contact("Xa"), coil("Yzone")],
        [el("MASTER_RELAY")],
        [el("MOVE", dest="i", src="0")],
        [el("LABEL", label="loop"), el("ADD", dest="i", op1="i", op2="1")],
        [el("LES", op1="i", op2="3"), el("GOTO", label="loop")],
        *([contact(f"R{k - 1}" if k else "Xa"), timer("TON", f"T{k}", 20000), coil(f"R{k}")] for k in range(chain)),
        [el("GOTO", label="end")],
        [el("SUBPROG", label="twice")],
        [el("ADD", dest="n", op1="n", op2="1")],
        [contact("Xshort"), el("RETURN")],
        [el("ADD", dest="n", op1="n", op2="1")],
        [el("ENDSUB", label="twice")],
        [el("LABEL", label="end"), contact("Xa"), timer("TON", "Tend", 30000), coil("Yend")],
    )


STEPS = [({"Xa": 1}, 1), ({}, 2), ({"Xshort": 1}, 1), ({"Xzone": 1}, 3), ({"Xskip": 1, "Xshort": 0}, 2),
         ({"Xskip": 0, "Xa": 0}, 1), ({"Xa": 1}, 40)]


def test_jumps_between_chunks_run_as_in_one_function():
    prog = jumping_program()
    assert observe(prog, STEPS, **EVERY_RUNG_A_CHUNK) == observe(prog, STEPS, **ONE_FUNCTION)


def test_a_program_past_the_thresholds_runs_as_in_one_function():
    prog = jumping_program(chain=150)
    assert sum(1 for _ in prog.elements()) > chunking.SINGLE_ELEMENTS
    assert observe(prog, STEPS, **AS_SHIPPED) == observe(prog, STEPS, **ONE_FUNCTION)


def test_a_fault_in_a_chunk_keeps_what_the_scan_did_before_it():
    prog = program([el("ADD", dest="n", op1="n", op2="1")], [contact("Xa"), el("LOCK")], [coil("Y")])
    steps = [({}, 2), ({"Xa": 1}, 1), ({}, 1)]
    assert observe(prog, steps, **EVERY_RUNG_A_CHUNK) == observe(prog, steps, **ONE_FUNCTION)
    runaway = program([el("LABEL", label="top")], [el("ADD", dest="n", op1="n", op2="1")],
                      [el("GOTO", label="top")])
    assert observe(runaway, [({}, 1)], **EVERY_RUNG_A_CHUNK) == observe(runaway, [({}, 1)], **ONE_FUNCTION)


@settings(max_examples=30)
@given(programs())
def test_any_program_runs_in_chunks_as_in_one_function(prog):
    inputs = sorted({str(e.args["name"]) for _, e in prog.elements()
                     if e.kind == "CONTACTS" and str(e.args["name"]).startswith("X")})
    steps = [({name: (k + i) % 2 for i, name in enumerate(inputs)}, 1 + k % 3) for k in range(4)]
    assert observe(prog, steps, **EVERY_RUNG_A_CHUNK) == observe(prog, steps, **ONE_FUNCTION)
