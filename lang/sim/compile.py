"""Compile a Program once into a Python scan function.

The function runs n scans in a row with every slot in a local variable:
`run(S, n, t0_us, E) -> scans done` loads the state list S, runs, and
stores it back (also when a fault stops it). A program with GOTO/GOSUB is
cut into segments (one per rung, plus one after each GOSUB) inside a
dispatch loop; one without jumps is straight-line code. The traced variant
also records each element's output power in E.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..model import Element, Program, Series
from ..values import is_literal, literal_value
from . import gen_io, gen_logic, gen_math, gen_timers  # noqa: F401  (they register the generators)
from .codegen import GENERATORS, CannotSimulate, Gen, Slot, timer_period
from .errors import BAD_JUMP, BAD_TIMER, NOT_SIMULATED, SimulationError, located
from .numbers import byte_needed

_JUMPS = {"GOTO", "GOSUB", "SUBPROG", "ENDSUB", "RETURN"}
_TIMERS = set(gen_timers.TIMERS)
_COUNTERS = gen_timers.COUNTERS


@dataclass
class Compiled:
    program: Program
    slots: list[Slot]
    index: dict[str, int]
    elements: list[tuple[int, int, Element]]  # element number -> (rung, index in rung, element)
    run: Callable
    run_traced: Callable


class JumpTable:
    """Where GOTO, GOSUB and SUBPROG go, as rung segments; return points
    after each GOSUB are extra segments numbered after the rungs."""

    def __init__(self, gen: Gen, program: Program):
        self.gen = gen
        self.count = len(program.rungs)
        self.labels: dict[str, int] = {}
        self.subprogs: dict[str, int] = {}
        self.endsubs: dict[str, int] = {}
        self.next_return = self.count + 1
        problems = []
        for rung, element in program.elements():
            label = str(element.args.get("label", ""))
            table = {"LABEL": self.labels, "SUBPROG": self.subprogs, "ENDSUB": self.endsubs}.get(element.kind)
            if table is None:
                continue
            if label in table:
                problems.append(located(BAD_JUMP, f"{element.kind}: only one {element.kind} '{label}' "
                                                  "is allowed", element))
            table[label] = rung
        for label, _rung in self.subprogs.items():
            if label not in self.endsubs:
                problems.append(located(BAD_JUMP, f"SUBPROG: ENDSUB '{label}' not found",
                                        _find(program, "SUBPROG", label)))
        if problems:
            raise SimulationError(problems)

    def goto_target(self, element: Element) -> int:
        label = str(element.args["label"])
        if is_literal(label):
            # a rung number, clamped to 1..rungs+1 as LDmicro does (rungs+1 = end of scan)
            return min(max(self.gen.literal(label), 1), self.count + 1) - 1
        if label not in self.labels:
            raise CannotSimulate(BAD_JUMP, f"GOTO: LABEL '{label}' not found")
        return self.labels[label]

    def gosub_target(self, element: Element) -> int:
        label = str(element.args["label"])
        if is_literal(label):
            raise CannotSimulate(BAD_JUMP, f"GOSUB: SUBPROG as a number '{label}' is not allowed")
        if label not in self.subprogs:
            raise CannotSimulate(BAD_JUMP, f"GOSUB: SUBPROG '{label}' not found")
        return self.subprogs[label] + 1

    def after_endsub(self, element: Element) -> int:
        return self.endsubs[str(element.args["label"])] + 1

    def new_return_point(self) -> int:
        self.next_return += 1
        return self.next_return - 1

    def start(self, segment: int) -> None:
        """End the current segment here and start `segment`, falling into it."""
        gen = self.gen
        if segment:
            gen.emit(f"seg = {segment}")
        gen.depth -= 1
        gen.emit(f"if seg == {segment}:")
        gen.depth += 1
        gen.emit("pass")

    split = start


def _find(program: Program, kind: str, label: str) -> Element | None:
    for _, element in program.elements():
        if element.kind == kind and str(element.args.get("label")) == label:
            return element
    return None


def _unsupported(program: Program) -> list:
    """Instructions without a simulation: those the table does not mark
    `sim`, and 9/14/16SEGMENTS, whose fonts LDmicro never defined."""
    problems = []
    for index, rung in enumerate(program.rungs):
        if rung.is_comment:
            continue
        for element in rung.elements():
            if not element.spec.supports("sim") or element.kind not in GENERATORS:
                what = "an empty rung" if element.kind == "PLACEHOLDER" else element.kind
                problems.append(located(NOT_SIMULATED, f"rung {index + 1}: {what} cannot be simulated",
                                        element))
    return problems


def variable_names(program: Program) -> tuple[set[str], dict[str, int]]:
    """Bit names, and the sizes LDmicro gives integer variables: VAR LIST
    sizes, with timers and counters sized to their values."""
    bits = {"ROverflowFlagV"}
    sizes = dict(program.var_sizes)
    cycle = program.settings.cycle_us
    for _, element in program.elements():
        for field in element.spec.fields:
            if field.kind == "bit" and element.args.get(field.name):
                bits.add(str(element.args[field.name]))
        if element.kind in ("SET_PWM", "RES") and str(element.args.get("name", "")).startswith("P"):
            bits.add(str(element.args["name"]))
        if element.kind in _TIMERS and isinstance(element.args.get("delay"), int) and cycle > 0:
            sizes[element.args["name"]] = min(4, byte_needed(element.args["delay"] // cycle))
        if element.kind in _COUNTERS:
            init, limit = str(element.args.get("init", "0")), str(element.args["max"])
            if is_literal(init) and is_literal(limit):
                try:
                    values = [literal_value(init), literal_value(limit)]
                except ValueError:
                    continue
                sizes[element.args["name"]] = max(byte_needed(v) for v in values)
    return bits, sizes


def counter_defs(program: Program) -> dict[str, Element]:
    """For RES C...: the first counter of that name, searching CTU, CTD, CTC
    then CTR elements (LDmicro's order)."""
    found: dict[str, Element] = {}
    for kind in _COUNTERS:
        for _, element in program.elements():
            if element.kind == kind:
                found.setdefault(str(element.args["name"]), element)
    return found


def _circuit(gen: Gen, node, p: str, tail: bool) -> None:
    if isinstance(node, Element):
        gen.generate(node, p)
    elif isinstance(node, Series):
        for i, item in enumerate(node.items):
            _circuit(gen, item, p, tail and i == len(node.items) - 1)
    else:
        # every branch sees the parallel's input; a branch's side effects
        # are visible to the branches below it
        out = None if tail and not gen.traced else gen.temp("o")
        if out:
            gen.emit(f"{out} = False")
        for branch in node.branches:
            b = gen.temp("b")
            gen.emit(f"{b} = {p}")
            _circuit(gen, branch, b, out is None)
            if out:
                gen.emit(f"{out} = {out} or {b}")
        if out:
            gen.emit(f"{p} = {out}")


def _initial_values(gen: Gen, program: Program) -> None:
    """What LDmicro's INIT VARS block (and its simulator, for set1 inputs)
    sets before the first scan, in program order so the last one wins."""
    def init(key: str, value) -> None:
        if key in gen.index:
            gen.slots[gen.index[key]].init = value

    for _, element in program.elements():
        kind = element.kind
        if kind == "CONTACTS" and element.args.get("set1") and str(element.args["name"]).startswith("X"):
            init(element.args["name"], True)
        elif kind in _COUNTERS and is_literal(str(element.args.get("init", "0"))):
            init(element.args["name"], literal_value(str(element.args.get("init", "0"))))
        elif kind == "TOF":
            name, delay = element.args["name"], element.args["delay"]
            if isinstance(delay, int):
                init(name, timer_period(gen, delay, int(element.args.get("adjust", 0) or 0), name))
            else:
                # LDmicro cannot start a variable-delay TOF; start it expired
                init(name, (1 << (8 * gen.size(name) - 1)) - 1)
        elif kind == "SEED_RANDOM":
            init(f"$seed_{element.args['name']}", DEFAULT_SEED)


# LDmicro seeds each SRAND sequence with C rand() at start-up; the
# simulator uses this fixed seed instead so that runs repeat.
DEFAULT_SEED = 1


def _generate(program: Program, bits, sizes, traced: bool, gen: Gen | None = None) -> Gen:
    gen = gen or Gen(program, sizes, bits)
    gen.traced = traced
    gen.counter_defs = counter_defs(program)
    gen.eeprom_next = 0
    jumps = any(e.kind in _JUMPS for _, e in program.elements())
    gen.jumps = JumpTable(gen, program) if jumps else None
    gen.depth = 3
    mcr = any(e.kind == "MASTER_RELAY" for _, e in program.elements())
    if mcr:
        gen.emit(f"{gen.bit('$mcr')} = True")
    if jumps:
        gen.emit("K = []")
        gen.emit("J = 0")
        gen.emit("seg = 0")
        gen.emit("while True:")
        gen.depth += 2
    for index, rung in enumerate(program.rungs):
        gen.rung, gen.position = index, -1
        if jumps:
            gen.jumps.start(index)
        if rung.is_comment or not rung.circuit.items:
            continue
        p = f"p{index}"
        gen.emit(f"{p} = {gen.bit('$mcr') if mcr else 'True'}")
        _circuit(gen, rung.circuit, p, True)
    if jumps:
        gen.depth -= 1
        gen.emit("break")
    return gen


def _function(gen: Gen, name: str, body: list[str]) -> list[str]:
    names = [f"v{i}" for i in range(len(gen.slots))]
    unpack = ", ".join(names) + ("," if len(names) == 1 else "")
    lines = [f"def {name}(S, n, t0, E):"]
    if names:
        lines.append(f"    {unpack} = S")
    lines += ["    done = 0", "    try:", "        while done < n:"]
    if gen.uses_time:
        lines.append(f"            now = t0 + done * {gen.cycle_us}")
    lines += body or ["            pass"]
    lines += ["            done += 1", "    except Fault as fault:", "        fault.done = done", "        raise",
              "    finally:"]
    lines.append(f"        S[:] = ({unpack})" if names else "        pass")
    lines.append("    return done")
    return lines


def compile_program(program: Program, peripherals) -> Compiled:
    if program.settings.cycle_us <= 0:
        raise SimulationError([located(BAD_TIMER, "the cycle time must be positive to simulate", None)])
    problems = _unsupported(program)
    if problems:
        raise SimulationError(problems)
    bits, sizes = variable_names(program)
    plain = _generate(program, bits, sizes, traced=False)
    fast_body = plain.lines
    # the traced variant must allocate the same slots in the same order
    plain.lines, plain.temp_count, plain.elements = [], 0, []
    traced = _generate(program, bits, sizes, traced=True, gen=plain)
    _initial_values(traced, program)
    source = "\n".join(_function(traced, "run", fast_body) + [""]
                       + _function(traced, "run_traced", traced.lines)) + "\n"
    namespace = dict(traced.namespace, PER=peripherals, U=peripherals.uart)
    exec(compile(source, "<ladder scan>", "exec"), namespace)
    return Compiled(program, traced.slots, traced.index, traced.elements,
                    namespace["run"], namespace["run_traced"])
