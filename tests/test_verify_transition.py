"""The prover's formula of a scan (lang/verify/transition.py) against the
simulator, scan by scan: random programs (test_compiler_random.py's
generator, on its C board: forward GOTOs and subroutines included) under
random inputs, bytes on the UART included, every name the simulator
shows compared after every scan. This is what makes a proof about the formula a proof about the
program the simulator runs and the back ends compile."""

from __future__ import annotations

import dataclasses

import pytest

z3 = pytest.importorskip("z3")

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from test_compiler_harness import Event
from test_compiler_random import C_BOARDS, FACTORIES, Case, _e, cases

from lang.model import Program, Rung, Series, Settings
from lang.semantics.lower import lower_program
from lang.sim import SimulationError, Simulator
from lang.sim.compile import SIMULATOR
from lang.verify.transition import UART_ARRIVALS, UART_QUEUE, Machine, NotModelled, Step, adc_input, taken_byte, took

BOARD = C_BOARDS[0]  # every instruction the C back end compiles
# the UART's instructions with a few others, at a cycle shorter than a byte's frame at 9600 baud
UART_KINDS = frozenset(("CONTACTS", "COIL", "OSR", "MOVE", "ADD", "UART_SEND", "UART_RECV", "UART_SEND_READY",
                        "UART_RECV_AVAIL", "FORMATTED_STRING"))
UART_BOARD = dataclasses.replace(BOARD, cycle_us=500, left_out=frozenset(FACTORIES) - UART_KINDS)
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


@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases((BOARD,)))
def test_the_formula_of_a_scan_agrees_with_the_simulator(case):
    _agree(case, SCANS)


@settings(max_examples=12, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(case=cases((UART_BOARD,)))
def test_the_uart_in_the_formula_agrees_with_the_simulator(case):
    _agree(case, 30)


def _agree(case, scans: int) -> None:
    """The prover's scan (lang.verify.transition.Step, built once) evaluated on
    the values the simulator holds, scan after scan."""
    program = case.program
    try:
        machine = Machine.of(lower_program(program, None, 1, SIMULATOR, trace=True), program.settings.cycle_us,
                             program.settings.baud)
        step = Step.of(machine)
    except NotModelled:
        assume(False)
    sim = Simulator(program)
    state = {name: z3.simplify(value) for name, value in machine.initial_state(_erased(machine)).items()}
    readings = {name: 0 for name in machine.adcs}
    received: list[int] = []  # bytes arrived on the UART and not taken yet
    for scan in range(min(scans, case.scans)):
        arrivals = 0
        for event in case.events:
            if event.scan != scan:
                continue
            if event.name == "uart":
                sim.uart_receive(bytes([event.value]))
                received.append(event.value)
                arrivals += 1
                continue
            sim.set(event.name, event.value)
            if event.name in readings:
                readings[event.name] = event.value
        inputs = {name: z3.BoolVal(bool(sim.value(name))) for name in machine.inputs}
        inputs.update({adc_input(name): z3.BitVecVal(value, 16) for name, value in readings.items()})
        if UART_QUEUE in machine.state_vars:
            # which UartTake ops take a byte does not depend on the bytes: each that does
            # gets the next byte received, in the scan's order
            inputs[UART_ARRIVALS] = z3.BitVecVal(arrivals, 8)
            inputs.update({taken_byte(j): z3.BitVecVal(0, 8) for j in machine.takes.values()})
            taking = _evaluate(step, state, inputs)
            inputs.update({taken_byte(j): z3.BitVecVal(received.pop(0), 8) for j in sorted(machine.takes.values())
                           if _value(taking(step.next[took(j)]))})
        after = _evaluate(step, state, inputs)
        sim.step()
        for name, expected in sim.variables().items():
            value = inputs[name] if name in inputs else after(step.next[name])
            assert _value(value) == expected, f"scan {scan + 1}: {name}"
        state = {name: after(step.next[name]) for name in state}


def _evaluate(step, state: dict, inputs: dict):
    """A function giving an expression over the step's placeholders its value
    for these values of the state and the inputs."""
    solver = z3.Solver()
    solver.add([step.state[name] == value for name, value in state.items()])
    solver.add([step.inputs[name] == value for name, value in inputs.items()])
    assert solver.check() == z3.sat
    model = solver.model()
    return lambda expr: model.eval(expr, model_completion=True)


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
    machine = Machine.of(lower_program(program, None, 1, SIMULATOR, trace=True), 10_000, 9600)
    after = machine.scan(machine.initial_state({}), {"Xgo": z3.BoolVal(True)})
    for name, expected in sim.variables().items():
        assert _value(after[name]) == expected, name


def test_a_subroutine_that_returns_early_agrees_with_the_simulator():
    """A RETURN half way through the subroutine, a call from the middle of a
    rung and a forward GOTO over the call, under every input combination."""
    contact = lambda name: _e("CONTACTS", name=name, negated=0)  # noqa: E731
    rungs = [Rung(Series([contact("Xa"), _e("GOSUB", label="sub"), _e("COIL", name="Ya", type=" ")])),
             Rung(Series([contact("Xe"), _e("GOTO", label="past")])),
             Rung(Series([contact("Xa"), _e("GOSUB", label="sub")])),
             Rung(Series([_e("LABEL", label="past"), _e("COIL", name="Yd", type="T")])),
             Rung(Series([_e("SUBPROG", label="sub")])),
             Rung(Series([contact("Xb"), _e("RETURN")])),
             Rung(Series([contact("Xc"), _e("ADD", dest="vn", op1="vn", op2="1"), _e("COIL", name="Yb", type="T")])),
             Rung(Series([_e("ENDSUB", label="sub")])),
             Rung(Series([contact("Yb"), _e("COIL", name="Yc", type=" ")]))]
    program = Program(Settings(cycle_us=10_000), rungs)
    inputs = ("Xa", "Xb", "Xc", "Xe")
    events = [Event(scan, name, (scan * 7 + 3) >> i & 1) for scan in range(32) for i, name in enumerate(inputs)]
    _agree(Case(program, events, 32), 32)
