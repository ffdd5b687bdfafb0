"""The prover's formula of a scan (lang/verify/transition.py) against the
simulator, scan by scan: random programs (test_compiler_random.py's
generator, on its C board, without the UART and GOSUB the prover does not
model) under random inputs, every name the simulator shows compared after
every scan. This is what makes a proof about the formula a proof about the
program the simulator runs and the back ends compile."""

from __future__ import annotations

import dataclasses

import pytest

z3 = pytest.importorskip("z3")

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from test_compiler_random import C_BOARDS, _e, cases

from lang.model import Program, Rung, Series, Settings
from lang.semantics.lower import lower_program
from lang.sim import SimulationError, Simulator
from lang.sim.compile import SIMULATOR
from lang.verify.transition import Machine, NotModelled, adc_input

UART = frozenset(("UART_SEND", "UART_RECV", "UART_SEND_READY", "UART_RECV_AVAIL", "FORMATTED_STRING"))
BOARD = dataclasses.replace(C_BOARDS[0], left_out=UART)
SCANS = 12  # the longest input sequence compared


def _value(expr) -> int:
    value = z3.simplify(expr)
    if z3.is_bool(value):
        assert z3.is_true(value) or z3.is_false(value), f"not a constant: {value}"
        return int(z3.is_true(value))
    assert z3.is_bv_value(value), f"not a constant: {value}"
    return value.as_signed_long()


def _erased(machine: Machine) -> dict:
    """The EEPROM as the simulator starts it: erased."""
    return {f"$eeprom@{address}": z3.BitVecVal(-1, 8 * size) for address, size in machine.eeprom.items()}


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases((BOARD,)))
def test_the_formula_of_a_scan_agrees_with_the_simulator(case):
    program = case.program
    assume(not any(e.kind == "GOSUB" for _, e in program.elements()))
    machine = Machine.of(lower_program(program, None, 1, SIMULATOR, trace=True))
    sim = Simulator(program)
    state = machine.initial_state(_erased(machine))
    scans = min(SCANS, case.scans)
    readings = {name: 0 for name in machine.adcs}
    for scan in range(scans):
        for event in case.events:
            if event.scan == scan:
                sim.set(event.name, event.value)
                if event.name in readings:
                    readings[event.name] = event.value
        inputs = {name: z3.BoolVal(bool(sim.value(name))) for name in machine.inputs}
        inputs.update({adc_input(name): z3.BitVecVal(value, 16) for name, value in readings.items()})
        try:
            after = machine.scan(state, inputs)
        except NotModelled:
            assume(False)
        sim.step()
        for name, expected in sim.variables().items():
            assert _value(after[name]) == expected, f"scan {scan + 1}: {name}"
        state = {name: z3.simplify(after[name]) for name in state}


BINARY = ("ADD", "SUB", "MUL", "DIV", "MOD", "AND", "OR", "XOR", "SHL", "SHR", "SR0", "ROL", "ROR")
UNARY = ("NEG", "NOT", "SWAP", "OPPOSITE", "BIN2BCD", "BCD2BIN")
BITS = ("SET_BIT", "CLEAR_BIT", "IF_BIT_SET", "IF_BIT_CLEAR")
COMPARISONS = ("EQU", "NEQ", "GRT", "GEQ", "LES", "LEQ")


def _sized(size: int):
    half = 1 << (8 * size - 1)
    return st.one_of(st.integers(-half, half - 1), st.sampled_from([0, 1, -1, half - 1, -half, 9, 10, 0x0909]))


@st.composite
def operations(draw, kind: str):
    """The instruction on variables of random sizes loaded with random values."""
    sizes = {name: draw(st.integers(1, 4)) for name in ("va", "vb", "vc")}
    a, b = draw(_sized(sizes["va"])), draw(_sized(sizes["vb"]))
    if kind in BINARY:
        op = _e(kind, dest="vc", op1="va", op2=draw(st.sampled_from(["vb", str(b)])))
    elif kind in ("SWAP", "OPPOSITE", "BIN2BCD", "BCD2BIN"):
        op = _e(kind, dest="vc", src="va")
    elif kind in UNARY:
        op = _e(kind, dest="vc", op1="va")
    elif kind in BITS:
        op = _e(kind, var="va", bit=draw(st.sampled_from(["vb", str(draw(st.integers(-2, 40)))])))
    else:
        op = _e(kind, op1="va", op2=draw(st.sampled_from(["vb", str(b)])))
    rungs = [Rung(Series([_e("MOVE", dest="va", src=str(a))])), Rung(Series([_e("MOVE", dest="vb", src=str(b))])),
             Rung(Series([_e("CONTACTS", name="Xgo", negated=0), op, _e("COIL", name="Yout", type=" ")]))]
    program = Program(Settings(cycle_us=10_000), rungs)
    program.var_sizes.update(sizes)
    return program


@pytest.mark.parametrize("kind", BINARY + UNARY + BITS + COMPARISONS)
@settings(max_examples=15, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_each_integer_operation_agrees_with_the_simulator(kind, data):
    program = data.draw(operations(kind))
    try:
        sim = Simulator(program)
        sim.set("Xgo", 1)
        sim.step()
    except SimulationError:
        assume(False)  # a literal shift count out of range, a division by zero, a value BCD cannot hold
    machine = Machine.of(lower_program(program, None, 1, SIMULATOR, trace=True))
    after = machine.scan(machine.initial_state({}), {"Xgo": z3.BoolVal(True)})
    for name, expected in sim.variables().items():
        assert _value(after[name]) == expected, name
