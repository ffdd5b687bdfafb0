"""Compile a Program once into a Python scan function.

The function runs n scans in a row with every slot in a local variable:
`run(S, n, t0_us, E) -> scans done` loads the state list S, runs, and
stores it back (also when a fault stops it). A program with GOTO/GOSUB is
cut into segments (one per rung, plus one after each GOSUB) inside a
dispatch loop; one without jumps is straight-line code. The traced variant
also records each element's output power in E.

Python's compiler needs kilobytes per line of source at once, so a large
program would cost gigabytes as one function. Its code is cut at rung starts
into chunks, each a function compiled as soon as it is written; the scan
function calls them in turn or, when the program jumps, calls the chunk
holding the next segment until the scan ends. The slots are then cells that
every chunk closes over, filled from S before the scans and copied back after.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
from dataclasses import dataclass
from types import CellType, CodeType, FunctionType

from .. import trampoline
from ..instructions import COUNTERS, JUMPS
from ..model import Element, Program, Series
from ..storage import DEFAULT_SEED, counter_defs, variable_names
from ..values import as_int, is_literal, literal_value
from . import gen_io, gen_logic, gen_math, gen_timers  # noqa: F401  (they register the generators)
from .codegen import GENERATORS, CannotSimulate, Gen, Slot, timer_period
from .errors import BAD_JUMP, BAD_TIMER, NOT_SIMULATED, SimulationError, located

# up to this many elements (about 100 rungs) one function is the faster:
# no calls, and one copy of the state in and out per batch of scans
SINGLE_ELEMENTS = 300
# about 10 MB of compiler memory a chunk
CHUNK_LINES = 4000
# a chunk also ends at this many slots: CPython 3.11 gets a frame that does
# not fit in its 16 KB block of frames from mmap, on every call
CHUNK_SLOTS = 256


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
        self.chunk = 0  # the chunk being written
        self.chunk_of: dict[int, int] = {}  # segment -> the chunk holding it
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

    def leave(self, segment: int) -> None:
        """End the current segment, going on to `segment`."""
        self.gen.emit(f"seg = {segment}")

    def enter(self, segment: int) -> None:
        gen = self.gen
        self.chunk_of[segment] = self.chunk
        gen.depth -= 1
        gen.emit(f"if seg == {segment}:")
        gen.depth += 1
        gen.emit("pass")

    def start(self, segment: int) -> None:
        """End the current segment here and start `segment`, falling into it."""
        if segment:
            self.leave(segment)
        self.enter(segment)

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


def _power(gen: Gen, prefix: str) -> str:
    """A variable for the power flowing in the rung. After a GOSUB the rung
    goes on where it was, which may be in another call of its chunk's
    function: a rung that calls a subroutine keeps these in slots."""
    name = gen.temp(prefix)
    return gen.slot(f"~{gen.rung}.{name}", "bit") if gen.calling else name


def _circuit(gen: Gen, node, p: str, tail: bool) -> trampoline.Call[None]:
    """The code of a block, flat at any depth: each parallel's power is a
    temporary, not a nested statement. A generator run by lang.trampoline,
    since blocks may nest deeper than Python's recursion limit."""
    if isinstance(node, Element):
        gen.generate(node, p)
    elif isinstance(node, Series):
        for i, item in enumerate(node.items):
            yield _circuit(gen, item, p, tail and i == len(node.items) - 1)
    else:
        # every branch sees the parallel's input; a branch's side effects
        # are visible to the branches below it
        out = None if tail and not gen.traced else _power(gen, "o")
        if out:
            gen.emit(f"{out} = False")
        for branch in node.branches:
            b = _power(gen, "b")
            gen.emit(f"{b} = {p}")
            yield _circuit(gen, branch, b, out is None)
            if out:
                gen.emit(f"{out} = {out} or {b}")
        if out:
            gen.emit(f"{p} = {out}")


def _initial_values(gen: Gen, program: Program) -> None:
    """What LDmicro's INIT VARS block (and its simulator, for set1 inputs)
    sets before the first scan, in program order so the last one wins."""
    def init(name: object, value: int) -> None:
        key = str(name)
        if key in gen.index:
            gen.slots[gen.index[key]].init = value

    for _, element in program.elements():
        kind = element.kind
        if kind == "CONTACTS" and element.args.get("set1") and str(element.args["name"]).startswith("X"):
            init(element.args["name"], True)
        elif kind in COUNTERS and is_literal(str(element.args.get("init", "0"))):
            init(element.args["name"], literal_value(str(element.args.get("init", "0"))))
        elif kind == "TOF":
            name, delay = element.args["name"], element.args["delay"]
            if isinstance(delay, int):
                init(name, timer_period(gen, delay, as_int(element.args.get("adjust", 0) or 0), str(name)))
            else:
                # LDmicro cannot start a variable-delay TOF; start it expired
                init(name, (1 << (8 * gen.size(str(name)) - 1)) - 1)
        elif kind == "SEED_RANDOM":
            init(f"$seed_{element.args['name']}", DEFAULT_SEED)



class _Writer:
    """Collects one scan function's code. With cells (a program of more than
    SINGLE_ELEMENTS elements) it is cut into chunks as it goes, each compiled
    at once; without, it is the body of one function."""

    def __init__(self, gen: Gen, name: str, cells: dict[int, CellType] | None):
        self.gen, self.name, self.cells = gen, name, cells
        self.chunks: list[Callable] = []
        self.body: list[str] = []
        gen.lines, gen.used = [], set()

    def rung(self, index: int) -> None:
        """Start rung `index`, in a new chunk if this one is full."""
        gen, jumps = self.gen, self.gen.jumps
        if jumps and index:
            jumps.leave(index)
        if self.cells is not None and (len(gen.lines) >= CHUNK_LINES or len(gen.used) >= CHUNK_SLOTS):
            self._cut()
        if jumps:
            jumps.enter(index)

    def finish(self) -> None:
        gen, jumps = self.gen, self.gen.jumps
        if self.cells is None:
            self.body = _JUMPS_START + _dispatch(gen.lines, "break") if jumps else gen.lines
            return
        if jumps:
            jumps.leave(jumps.count)  # the end of the scan
        self._cut()
        if not jumps:
            self.body = [f"{chunk.__name__}(now, E)" for chunk in self.chunks]
            return
        # segment jumps.count, the end of the scan, has no chunk
        table = f"{self.name}_at"
        gen.namespace[table] = [self.chunks[jumps.chunk_of[segment]] if segment in jumps.chunk_of else None
                                for segment in range(jumps.next_return)]
        self.body = _JUMPS_START + [f"while seg != {jumps.count}:",
                                    f"    seg, J = {table}[seg](now, E, seg, J, K)"]

    def function(self) -> Callable:
        """The scan function; made once both variants have allocated every
        slot, since one that is not chunked keeps them all in locals."""
        gen = self.gen
        if self.cells is not None:
            lines = _function(gen, self.name, self.body, ["for load in LOAD:", "    load(S)"],
                              ["for store in STORE:", "    store(S)"], timed=True)
            return _closure(lines, _relay(gen), self.cells, gen.namespace)
        names = ", ".join(f"v{i}" for i in range(len(gen.slots))) + ","
        load, store = ([f"{names} = S"], [f"S[:] = ({names})"]) if gen.slots else ([], [])
        source = "\n".join(_function(gen, self.name, self.body, load, store, gen.uses_time)) + "\n"
        exec(compile(source, "<ladder scan>", "exec"), gen.namespace)
        function = gen.namespace[self.name]
        assert callable(function)  # the exec just defined it
        return function

    def _cut(self) -> None:
        gen = self.gen
        name = f"{self.name}_{len(self.chunks)}"
        if gen.jumps:
            lines = [f"def {name}(now, E, seg, J, K):", *_indented(_dispatch(gen.lines, "return seg, J"), 1)]
        else:
            lines = [f"def {name}(now, E):", *_indented(gen.lines or ["pass"], 1)]
        assert self.cells is not None  # only a writer with cells cuts
        chunk = gen.namespace[name] = _closure(lines, gen.used, self.cells, gen.namespace)
        self.chunks.append(chunk)
        gen.lines, gen.used = [], set()
        if gen.jumps:
            gen.jumps.chunk = len(self.chunks)


# every scan starts at segment 0 with no jumps made and no GOSUB to return from
_JUMPS_START = ["K = []", "J = 0", "seg = 0"]


def _indented(lines: list[str], depth: int) -> list[str]:
    pad = "    " * depth
    return [pad + line for line in lines]


def _dispatch(lines: list[str], end: str) -> list[str]:
    """Segments in a loop: a jump sets seg and starts the loop again. In a
    chunk, a jump to another chunk's segment matches none and comes out."""
    return ["while True:", *_indented(lines, 1), f"    {end}"]


def _closure(lines: list[str], used, cells: dict[int, CellType], namespace: dict) -> Callable:
    """Compile the function `lines` define as a closure over the cells of the
    slots `used`: every chunk reads and writes the same variables, nearly as
    fast as locals, with nothing to copy in and out around each call."""
    names = [f"v{i}" for i in sorted(used)]
    if names:
        lines = [lines[0], f"    nonlocal {', '.join(names)}", *lines[1:]]
    # the wrapper only gives the names a scope to be free in: its cells are
    # never made, the function is rebuilt over the shared ones
    wrapper = ["def _():", *([f"    {' = '.join(names)} = None"] if names else []), *_indented(lines, 1)]
    module = compile("\n".join(wrapper) + "\n", "<ladder scan>", "exec")
    outer = next(c for c in module.co_consts if isinstance(c, CodeType))
    code = next(c for c in outer.co_consts if isinstance(c, CodeType))
    return FunctionType(code, namespace, code.co_name, None, tuple(cells[int(v[1:])] for v in code.co_freevars))


def _sync(gen: Gen, cells: dict[int, CellType]) -> None:
    """LOAD and STORE, which copy every slot from S into its cell and back,
    CHUNK_SLOTS at a time, around a batch of scans."""
    loads, stores = [], []
    for start in range(0, len(gen.slots), CHUNK_SLOTS):
        block = range(start, min(start + CHUNK_SLOTS, len(gen.slots)))
        names = ", ".join(f"v{i}" for i in block) + ","
        loads.append(_closure(["def load(S):", f"    {names} = S[{block.start}:{block.stop}]"], block, cells,
                              gen.namespace))
        stores.append(_closure(["def store(S):", f"    S[{block.start}:{block.stop}] = {names}"], block, cells,
                               gen.namespace))
    gen.namespace.update(LOAD=loads, STORE=stores)


def _generate(gen: Gen, program: Program, name: str, traced: bool, cells: dict[int, CellType] | None) -> _Writer:
    gen.traced = traced
    gen.elements = []
    gen.counter_defs = counter_defs(program)
    gen.eeprom_next = 0
    jumps = any(e.kind in JUMPS for _, e in program.elements())
    gen.jumps = JumpTable(gen, program) if jumps else None
    gen.depth = 1 if jumps else 0
    mcr = any(e.kind == "MASTER_RELAY" for _, e in program.elements())
    writer = _Writer(gen, name, cells)
    for index, rung in enumerate(program.rungs):
        # temporaries die with their rung, so each rung reuses the same few
        # names: a chunk's frame holds its slots and little more
        gen.rung, gen.position, gen.temp_count = index, -1, 0
        writer.rung(index)
        if rung.is_comment or not rung.circuit.items:
            continue
        gen.calling = jumps and any(e.kind == "GOSUB" for e in rung.elements())
        p = _power(gen, "p")
        gen.emit(f"{p} = {gen.bit('$mcr') if mcr else 'True'}")
        trampoline.run(_circuit(gen, rung.circuit, p, True))
    writer.finish()
    return writer


def _relay(gen: Gen) -> set[int]:
    """The master relay's slot, if the program has one."""
    return {gen.index["$mcr"]} if "$mcr" in gen.index else set()


def _scan_start(gen: Gen) -> list[str]:
    """Every scan starts with the master relay closed."""
    return [f"v{mcr} = True" for mcr in _relay(gen)]


def _function(gen: Gen, name: str, body: list[str], load: list[str], store: list[str], timed: bool) -> list[str]:
    lines = [f"def {name}(S, n, t0, E):", *_indented(load, 1), "    done = 0", "    try:", "        while done < n:"]
    if timed:
        lines.append(f"            now = t0 + done * {gen.cycle_us}")
    lines += _indented(_scan_start(gen) + body or ["pass"], 3)
    lines += ["            done += 1", "    except Fault as fault:", "        fault.done = done", "        raise",
              "    finally:", *_indented(store or ["pass"], 2), "    return done"]
    return lines


def compile_program(program: Program, peripherals) -> Compiled:
    if program.settings.cycle_us <= 0:
        raise SimulationError([located(BAD_TIMER, "the cycle time must be positive to simulate", None)])
    problems = _unsupported(program)
    if problems:
        raise SimulationError(problems)
    bits, sizes = variable_names(program)
    gen = Gen(program, sizes, bits)
    gen.namespace.update(PER=peripherals, U=peripherals.uart)
    # a slot's cell is made when a chunk first uses it
    cells: dict[int, CellType] | None = defaultdict(CellType) if sum(1 for _ in program.elements()) > SINGLE_ELEMENTS else None
    # the two variants share one Gen, so that they number the slots alike
    writers = [_generate(gen, program, "run", False, cells), _generate(gen, program, "run_traced", True, cells)]
    _initial_values(gen, program)
    if cells is not None:
        _sync(gen, cells)
    run, run_traced = (writer.function() for writer in writers)
    return Compiled(program, gen.slots, gen.index, gen.elements, run, run_traced)
