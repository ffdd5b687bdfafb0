"""Bounded model checking and k-induction over the program's scans.

Two unrollings of the scan (lang.verify.transition) share every property:
one from power-up, which looks for a counterexample scan by scan (the base
case), and one from any state at all, which tries to show that k scans in
a row where the property held are always followed by one where it holds
(the induction step). At depth k: no counterexample in scans 0..k-1 and the
step of length k together prove the property for every scan of every input
sequence.

A property is a monitor over the values after each scan: `bad` says the
property has just failed. `always C` fails where C does not hold, `never C`
where it does; `R within N scans after T` keeps, as monitor state, how many
scans ago the oldest trigger still waiting for its response came, and fails
when that reaches N. `reachable C` is the search for a scan where C holds:
found from power-up, it is proved (the input sequence is its witness); shown
never to hold by induction, it fails.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import z3

from ..properties import Property
from ..sim.scenario import Logic
from .transition import Machine, adc_input, eeprom_name

SMT = Logic(all=lambda values: z3.And(*values), any=lambda values: z3.Or(*values), negate=z3.Not,
            implies=z3.Implies)
WIDE = 64

PROVED, FAILS, UNKNOWN = "proved", "fails", "unknown"


@dataclass
class Witness:
    """An input sequence from power-up: each scan's X inputs and A/D
    readings, the EEPROM's contents at power-up (by address, the value of
    the variable kept there), and the scan where the property fails (for a
    reachable property: is reached); for `within`, the scan of the trigger."""

    inputs: list[dict[str, int]]
    eeprom: dict[int, int]
    scan: int
    trigger: int | None = None


@dataclass
class Result:
    prop: Property
    verdict: str  # PROVED, FAILS or UNKNOWN
    depth: int  # scans from power-up searched without a counterexample (or up to the witness)
    k: int | None = None  # the induction's length, when it decided
    witness: Witness | None = None
    why: str = ""  # what stopped the search short of the bound (a timeout)
    seconds: float = 0.0


class Unrolling:
    """The scans of one run, each with the values after it as the
    properties read them; `start` is power-up or any state at all."""

    def __init__(self, machine: Machine, solver: z3.Solver, tag: str, from_power_up: bool):
        self.machine, self.solver, self.tag = machine, solver, tag
        first = machine.fresh_state(f"{tag}0")
        self.first = first
        if from_power_up:
            eeprom = {name: first[name] for name in machine.eeprom_names()}
            start = machine.initial_state(eeprom)
            solver.add([first[name] == value for name, value in start.items() if name not in eeprom])
        self.state = first
        self.inputs: list[dict[str, z3.ExprRef]] = []
        self.after: list[dict[str, z3.ExprRef]] = []

    def extend(self) -> None:
        k = len(self.after)
        inputs = self.machine.fresh_inputs(f"{self.tag}{k}")
        self.solver.add(self.machine.input_bounds(inputs))
        env = self.machine.scan(self.state, inputs)
        following = self.machine.fresh_state(f"{self.tag}{k + 1}")
        self.solver.add([following[name] == env[name] for name in following])
        self.state = following
        self.inputs.append(inputs)
        self.after.append({**following, **inputs})


def read(values: dict[str, z3.ExprRef], name: str) -> z3.BitVecRef:
    """A signal as a property reads it: its signed value (a bit is 0 or 1)."""
    value = values[name]
    if z3.is_bool(value):
        return z3.If(value, z3.BitVecVal(1, WIDE), z3.BitVecVal(0, WIDE))
    return z3.SignExt(WIDE - value.size(), value)


class Monitor:
    """A property's `bad` for each scan of one unrolling."""

    def __init__(self, prop: Property, scans: int, unrolling: Unrolling, from_power_up: bool):
        self.prop, self.scans, self.unrolling = prop, scans, unrolling
        self.bad: list[z3.BoolRef] = []
        self.waiting: z3.ArithRef = z3.IntVal(-1)
        if prop.kind == "within" and not from_power_up:
            # any count a run where the property held may have reached
            self.waiting = z3.Int(f"waiting{id(self)}")
            unrolling.solver.add(self.waiting >= -1, self.waiting < scans)

    def upto(self, k: int) -> list[z3.BoolRef]:
        while len(self.bad) <= k:
            scan = len(self.bad)
            while len(self.unrolling.after) <= scan:
                self.unrolling.extend()
            self.bad.append(self._bad(self.unrolling.after[scan]))
        return self.bad[:k + 1]

    def _bad(self, values: dict[str, z3.ExprRef]) -> z3.BoolRef:
        prop = self.prop

        def holds(condition) -> z3.BoolRef:
            return condition.evaluate(lambda name: read(values, name), SMT)

        if prop.kind == "always":
            return z3.Not(holds(prop.condition))
        if prop.kind in ("never", "reachable"):
            return holds(prop.condition)
        assert prop.trigger is not None
        response, trigger = holds(prop.condition), holds(prop.trigger)
        self.waiting = z3.If(response, -1, z3.If(self.waiting >= 0, self.waiting + 1, z3.If(trigger, 0, -1)))
        return self.waiting >= self.scans


@dataclass
class Search:
    """The two unrollings and each property's monitors on them."""

    machine: Machine
    cycle_us: int
    deadline: float
    base: z3.Solver = field(default_factory=z3.Solver)
    step: z3.Solver = field(default_factory=z3.Solver)

    def __post_init__(self):
        self.from_power_up = Unrolling(self.machine, self.base, "b", True)
        self.from_anywhere = Unrolling(self.machine, self.step, "s", False)

    def check(self, solver: z3.Solver, *facts: z3.BoolRef) -> z3.CheckSatResult:
        left = self.deadline - time.monotonic()
        if left <= 0:
            return z3.unknown
        solver.set("timeout", max(1, int(left * 1000)))
        solver.push()
        solver.add(*facts)
        result = solver.check()
        if result != z3.sat:
            solver.pop()
        return result


def prove(machine: Machine, properties: list[Property], cycle_us: int, bound: int, timeout_s: float) -> list[Result]:
    """Each property's result, searching up to `bound` scans from power-up
    within `timeout_s` seconds for all of them."""
    started = time.monotonic()
    search = Search(machine, cycle_us, started + timeout_s)
    results = []
    for prop in properties:
        began = time.monotonic()
        result = _prove_one(search, prop, bound)
        result.seconds = time.monotonic() - began
        results.append(result)
    return results


def _prove_one(search: Search, prop: Property, bound: int) -> Result:
    scans = prop.scans(search.cycle_us)
    base = Monitor(prop, scans, search.from_power_up, True)
    step = Monitor(prop, scans, search.from_anywhere, False)
    reach = prop.kind == "reachable"
    for k in range(bound):
        bad = base.upto(k)[k]
        found = search.check(search.base, bad)
        if found == z3.sat:
            witness = _witness(search, prop, k, scans, bad)
            return Result(prop, PROVED if reach else FAILS, k + 1 if reach else k, witness=witness)
        if found == z3.unknown:
            return Result(prop, UNKNOWN, k, why="the time allowed ran out")
        # held at scan k whatever the inputs: a fact about every run from power-up
        search.base.add(z3.Not(bad))
        assumed = step.upto(k + 1)
        stepped = search.check(search.step, *[z3.Not(b) for b in assumed[:-1]], assumed[-1])
        if stepped == z3.sat:
            search.step.pop()
        elif stepped == z3.unsat:
            return Result(prop, FAILS if reach else PROVED, k + 1, k=k + 1)
        else:
            return Result(prop, UNKNOWN, k + 1, why="the time allowed ran out")
    return Result(prop, UNKNOWN, bound)


def _witness(search: Search, prop: Property, k: int, scans: int, bad: z3.BoolRef) -> Witness:
    """The input sequence of the model found (left on the solver's stack, which
    this pops); one from an erased EEPROM, as the simulator starts, when
    there is one."""
    solver, machine, unrolling = search.base, search.machine, search.from_power_up
    model = solver.model()
    solver.pop()
    if machine.eeprom:
        erased = machine.erased(unrolling.first)
        if search.check(solver, bad, *erased) == z3.sat:
            model = solver.model()
            solver.pop()
    inputs = []
    for values in unrolling.inputs[:k + 1]:
        scan = {name: int(z3.is_true(model.eval(values[name], model_completion=True))) for name in machine.inputs}
        scan.update({name: model.eval(values[adc_input(name)], model_completion=True).as_long()
                     for name in machine.adcs})
        inputs.append(scan)
    eeprom = {}
    for address, size in machine.eeprom.items():
        raw = model.eval(unrolling.first[eeprom_name(address)], model_completion=True).as_long()
        eeprom[address] = raw - (1 << 8 * size) if raw >> (8 * size - 1) else raw
    trigger = k - scans if prop.kind == "within" else None
    return Witness(inputs, eeprom, k, trigger)
