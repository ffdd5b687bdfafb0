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
from dataclasses import dataclass, field, replace

import z3

from ..properties import Property
from ..sim.scenario import Implies, Logic
from .transition import UART_ARRIVALS, UART_QUEUE, Machine, Step, adc_input, eeprom_name, taken_byte, took

SMT = Logic(all=lambda values: z3.And(*values), any=lambda values: z3.Or(*values), negate=z3.Not,
            implies=z3.Implies)
WIDE = 64
WAITING = 32  # bits of a `within` monitor's count of scans

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
    uart: list[bytes] = field(default_factory=list)  # the bytes arriving before each scan


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
    """The scans of a run, shared by every property: the value of each name
    at each scan, and the constraint that makes a state's value after scan
    k the scan's result. A state before the first scan is power-up's (the
    EEPROM's contents free) or, `from_anywhere`, free."""

    def __init__(self, step: Step, tag: str, from_anywhere: bool):
        self.step, self.tag, self.from_anywhere = step, tag, from_anywhere
        machine = step.machine
        eeprom = machine.eeprom_names()
        self.first = machine.fresh_state(f"{tag}0")
        self.start = dict(self.first) if from_anywhere else \
            machine.initial_state({name: self.first[name] for name in eeprom})
        self._values: dict[tuple[str, int], z3.ExprRef] = {}
        self._links: dict[tuple[str, int], z3.BoolRef] = {}

    def value(self, name: str, scan: int) -> z3.ExprRef:
        """A state's value before `scan` (0: the start), or an input's during it."""
        key = (name, scan)
        if key not in self._values:
            if name in self.step.inputs:
                template = self.step.inputs[name]
            elif scan == 0:
                return self.start[name]
            else:
                template = self.step.state[name]
            self._values[key] = z3.Const(f"{name}@{self.tag}{scan}", template.sort())
        return self._values[key]

    def after(self, name: str, scan: int) -> z3.ExprRef:
        """The value a property reads after `scan`."""
        return self.value(name, scan) if name in self.step.inputs else self.value(name, scan + 1)

    def computed(self, name: str, scan: int) -> z3.ExprRef:
        """What scan `scan` computes for `name` (a state, or whether a UartTake took a byte)."""
        step = self.step
        pairs = [(step.state[r] if r in step.state else step.inputs[r], self.value(r, scan)) for r in step.reads[name]]
        return z3.substitute(step.next[name], *pairs) if pairs else step.next[name]

    def link(self, name: str, scan: int) -> z3.BoolRef:
        """The state `name` after `scan` is what the scan computes."""
        key = (name, scan)
        if key not in self._links:
            self._links[key] = self.value(name, scan + 1) == self.computed(name, scan)
        return self._links[key]


class Frame:
    """A solver that holds one property's cone of the unrolling, scan by scan."""

    def __init__(self, unrolling: Unrolling, cone: set[str]):
        self.unrolling = unrolling
        # a solver for bit-vectors alone: several times faster than the default's
        self.solver = z3.SolverFor("QF_BV")
        step = unrolling.step
        self.states = sorted(n for n in cone if n in step.state)
        self.inputs = sorted(n for n in cone if n in step.inputs)
        self.scans = 0
        if unrolling.from_anywhere:
            start = {name: unrolling.value(name, 0) for name in self.states}
            self.solver.add(step.machine.invariants(start))

    def cover(self, scan: int) -> None:
        """Constrain the scans up to `scan`."""
        while self.scans <= scan:
            k, unrolling = self.scans, self.unrolling
            self.solver.add([unrolling.link(name, k) for name in self.states])
            machine = unrolling.step.machine
            self.solver.add([fact for n in self.inputs for fact in machine.bounds(n, unrolling.value(n, k))])
            self.scans += 1


def read(value: z3.ExprRef) -> z3.BitVecRef:
    """A signal as a property reads it: its signed value (a bit is 0 or 1)."""
    if z3.is_bool(value):
        return z3.If(value, z3.BitVecVal(1, WIDE), z3.BitVecVal(0, WIDE))
    return z3.SignExt(WIDE - value.size(), value)


class Monitor:
    """A property's `bad` for each scan of one unrolling."""

    def __init__(self, prop: Property, scans: int, frame: Frame):
        self.prop, self.scans, self.frame = prop, scans, frame
        self.bad: list[z3.BoolRef] = []
        self.waiting: z3.BitVecRef = z3.BitVecVal(-1, WAITING)
        if prop.kind == "within" and frame.unrolling.from_anywhere:
            # any count a run where the property held may have reached
            self.waiting = z3.BitVec(f"waiting@{frame.unrolling.tag}", WAITING)
            frame.solver.add(self.waiting >= -1, self.waiting < scans)

    def upto(self, k: int) -> list[z3.BoolRef]:
        self.frame.cover(k)
        while len(self.bad) <= k:
            self.bad.append(self._bad(len(self.bad)))
        return self.bad[:k + 1]

    def _bad(self, scan: int) -> z3.BoolRef:
        prop, unrolling = self.prop, self.frame.unrolling

        def holds(condition) -> z3.BoolRef:
            return condition.evaluate(lambda name: read(unrolling.after(name, scan)), SMT)

        if prop.kind == "always":
            return z3.Not(holds(prop.condition))
        if prop.kind in ("never", "reachable"):
            return holds(prop.condition)
        assert prop.trigger is not None
        response, trigger = holds(prop.condition), holds(prop.trigger)
        none, waiting = z3.BitVecVal(-1, WAITING), self.waiting
        # the count is a state of its own: a variable each scan, linked to the last
        self.waiting = z3.BitVec(f"waiting@{self.frame.unrolling.tag}{scan + 1}", WAITING)
        self.frame.solver.add(self.waiting == z3.If(response, none, z3.If(
            waiting >= 0, waiting + 1, z3.If(trigger, z3.BitVecVal(0, WAITING), none))))
        return self.waiting >= self.scans


class Search:
    """The two unrollings every property shares, and the time left."""

    def __init__(self, machine: Machine, cycle_us: int, deadline: float):
        self.step = Step.of(machine)
        self.machine, self.cycle_us, self.deadline = machine, cycle_us, deadline
        self.from_power_up = Unrolling(self.step, "b", from_anywhere=False)
        self.from_anywhere = Unrolling(self.step, "s", from_anywhere=True)

    def check(self, solver: z3.Solver, *facts: z3.BoolRef) -> z3.CheckSatResult:
        """Whether the facts can hold; on sat they stay pushed (the caller pops)."""
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
    if prop.trigger is not None:
        # a response in the very scan of its trigger is a stronger property whose
        # induction is short, where the count of scans waited would need as many
        same_scan = replace(prop, kind="always", condition=Implies(prop.trigger, prop.condition), trigger=None)
        lemma = _prove_one(search, same_scan, bound)
        if lemma.verdict == PROVED:
            return replace(lemma, prop=prop)
    scans = prop.scans(search.cycle_us)
    step = search.step
    cone = step.cone(prop.names())
    base = Monitor(prop, scans, Frame(search.from_power_up, cone))
    induction = Monitor(prop, scans, Frame(search.from_anywhere, cone))
    reach = prop.kind == "reachable"
    for k in range(bound):
        bad = base.upto(k)[k]
        found = search.check(base.frame.solver, bad)
        if found == z3.sat:
            witness = _witness(search, base.frame, prop, k, scans, bad)
            return Result(prop, PROVED if reach else FAILS, k + 1 if reach else k, witness=witness)
        if found == z3.unknown:
            return Result(prop, UNKNOWN, k, why="the time allowed ran out")
        # held at scan k whatever the inputs: a fact about every run from power-up
        base.frame.solver.add(z3.Not(bad))
        assumed = induction.upto(k + 1)
        stepped = search.check(induction.frame.solver, *[z3.Not(b) for b in assumed[:-1]], assumed[-1])
        if stepped == z3.sat:
            induction.frame.solver.pop()
        elif stepped == z3.unsat:
            return Result(prop, FAILS if reach else PROVED, k + 1, k=k + 1)
        else:
            return Result(prop, UNKNOWN, k + 1, why="the time allowed ran out")
    return Result(prop, UNKNOWN, bound)


def _witness(search: Search, frame: Frame, prop: Property, k: int, scans: int, bad: z3.BoolRef) -> Witness:
    """The input sequence of the model found (left on the solver's stack, which
    this pops); one from an erased EEPROM, as the simulator starts, when
    there is one. Inputs outside the property's cone are 0."""
    solver, machine, unrolling = frame.solver, search.machine, search.from_power_up
    model = solver.model()
    solver.pop()
    erased = [fact for fact in machine.erased(unrolling.first)]
    if machine.eeprom and search.check(solver, bad, *erased) == z3.sat:
        model = solver.model()
        solver.pop()

    def value(expr: z3.ExprRef) -> int:
        found = model.eval(expr, model_completion=True)
        return int(z3.is_true(found)) if z3.is_bool(found) else found.as_signed_long()

    inputs = []
    for scan in range(k + 1):
        values = {name: value(unrolling.value(name, scan)) for name in machine.inputs}
        values.update({name: value(unrolling.value(adc_input(name), scan)) for name in machine.adcs})
        inputs.append(values)
    eeprom = {address: value(unrolling.first[eeprom_name(address)]) for address in machine.eeprom}
    trigger = k - scans if prop.kind == "within" else None
    return Witness(inputs, eeprom, k, trigger, _received(machine, unrolling, value, k))


def _received(machine: Machine, unrolling: Unrolling, value, k: int) -> list[bytes]:
    """The bytes arriving before each scan: as many as the model says, the
    first of them the bytes the program took, in the order it took them."""
    if UART_QUEUE not in machine.state_vars:
        return []
    arrivals = [value(unrolling.value(UART_ARRIVALS, scan)) for scan in range(k + 1)]
    taken = [value(unrolling.value(taken_byte(j), scan)) & 0xFF
             for scan in range(k + 1) for j in sorted(machine.takes.values())
             if value(unrolling.computed(took(j), scan))]
    stream = iter(taken + [0] * sum(arrivals))
    return [bytes(next(stream) for _ in range(count)) for count in arrivals]
