"""Compile a Program once into a Python scan function: the lowering
(lang.semantics) writes its intermediate code, traced, and the simulator's
back end (lang/sim/emit.py) writes each op as Python.

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

from ..families import Family
from ..instructions import JUMPS
from ..model import Element, Program
from ..semantics import errors as lowering
from ..semantics import ir
from ..semantics.lower import LOWERINGS, Jumps, lower_program, rung_label
from .codegen import Gen, Slot
from .emit import emit_ops
from .errors import BAD_JUMP, BAD_OPERAND, BAD_TIMER, NOT_SIMULATED, SimulationError, located

# the lowering for the simulator: every instruction the table marks `sim`
SIMULATOR = Family("sim", "the simulator", ())
# the code of each kind of problem the lowering meets
LOWERING_CODES = {lowering.OPERAND: BAD_OPERAND, lowering.TIMER: BAD_TIMER, lowering.JUMP: BAD_JUMP,
                  lowering.UNSUPPORTED: NOT_SIMULATED, lowering.EEPROM: BAD_OPERAND}

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
    sends_uart: bool = False  # some instruction transmits on the UART


class JumpTable:
    """The segments GOTO, GOSUB and RETURN go to: one per rung, the end of
    the scan, then the return points after each GOSUB."""

    def __init__(self, gen: Gen, program: Program):
        self.gen = gen
        self.count = len(program.rungs)
        self.segments = {rung_label(index): index for index in range(self.count + 1)}
        self.next_return = self.count + 1
        self.chunk = 0  # the chunk being written
        self.chunk_of: dict[int, int] = {}  # segment -> the chunk holding it

    def segment(self, label: str) -> int:
        return self.segments[label]

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

    def split(self, segment: int) -> None:
        """End the current segment here and start `segment`, falling into it."""
        self.leave(segment)
        self.enter(segment)


def _check_jumps(program: Program, elements: list[tuple[int, Element]]) -> None:
    """Every LABEL, SUBPROG and ENDSUB once, every SUBPROG with its ENDSUB."""
    jumps = Jumps(program, elements)
    problems = [located(BAD_JUMP, f"{e.kind}: only one {e.kind} '{e.args.get('label', '')}' is allowed", e)
                for e in jumps.repeated]
    problems += [located(BAD_JUMP, f"SUBPROG: ENDSUB '{e.args.get('label', '')}' not found", e)
                 for e in jumps.unended()]
    if problems:
        raise SimulationError(problems)


def _unsupported(program: Program) -> list:
    """Instructions without a simulation: those the table does not mark `sim`."""
    problems = []
    for index, rung in enumerate(program.rungs):
        if rung.is_comment:
            continue
        for element in rung.elements():
            if not element.spec.supports("sim") or element.kind not in LOWERINGS:
                what = "an empty rung" if element.kind == "PLACEHOLDER" else element.kind
                problems.append(located(NOT_SIMULATED, f"rung {index + 1}: {what} cannot be simulated",
                                        element))
    return problems


def _initial_values(gen: Gen, code: ir.Code, elements: list[Element]) -> None:
    """What LDmicro's INIT VARS block sets before the first scan (the
    lowering's `init`) and what its simulator sets: the inputs a contact
    marks `set1` start at 1."""
    def init(name: str, value: int) -> None:
        if name in gen.index:
            gen.slots[gen.index[name]].init = value

    for op in code.init:
        assert isinstance(op, ir.Move) and isinstance(op.dst, ir.Var) and isinstance(op.src, ir.Const)
        init(op.dst.name, op.src.value)
    for element in elements:
        if element.kind == "CONTACTS" and element.args.get("set1") and str(element.args["name"]).startswith("X"):
            init(str(element.args["name"]), True)


class _Writer:
    """Collects one scan function's code. With cells (a program of more than
    SINGLE_ELEMENTS elements) it is cut into chunks as it goes, each compiled
    at once; without, it is the body of one function."""

    def __init__(self, gen: Gen, name: str, cells: dict[int, CellType] | None):
        self.gen, self.name, self.cells = gen, name, cells
        self.chunks: list[Callable] = []
        self.body: list[str] = []
        self.start: list[str] = []  # every scan's first lines, before the rungs
        self.start_used: set[int] = set()
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
            lines = _function(gen, self.name, self.start, self.body, ["for load in LOAD:", "    load(S)"],
                              ["for store in STORE:", "    store(S)"], timed=True)
            return _closure(lines, self.start_used, self.cells, gen.namespace)
        names = ", ".join(f"v{i}" for i in range(len(gen.slots))) + ","
        load, store = ([f"{names} = S"], [f"S[:] = ({names})"]) if gen.slots else ([], [])
        source = "\n".join(_function(gen, self.name, self.start, self.body, load, store, gen.uses_time)) + "\n"
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


def _generate(gen: Gen, code: ir.Code, name: str, traced: bool, cells: dict[int, CellType] | None,
              jumps: bool) -> _Writer:
    gen.traced = traced
    gen.elements = []
    program = gen.program
    gen.jumps = JumpTable(gen, program) if jumps else None
    writer = _Writer(gen, name, cells)
    start, rungs = _rungs(code.scan, len(program.rungs))
    writer.start = _lines(gen, start)
    writer.start_used = set(gen.used)
    gen.lines, gen.used = [], set()
    gen.depth = 1 if jumps else 0
    for index, ops in enumerate(rungs):
        writer.rung(index)
        gen.new_rung(index, jumps and any(isinstance(op, ir.Call) for op in _walk(ops)))
        emit_ops(gen, ops, each=lambda: _return_point(gen))
    writer.finish()
    return writer


def _return_point(gen: Gen) -> None:
    """After a GOSUB's block, the segment where its RETURN comes back: the
    rest of the rung."""
    if gen.return_point is not None:
        assert gen.jumps is not None
        gen.jumps.split(gen.return_point)
        gen.return_point = None


def _rungs(scan: list[ir.Op], count: int) -> tuple[list[ir.Op], list[list[ir.Op]]]:
    """The code before the first rung (every scan's start), and each rung's."""
    labels = {rung_label(index) for index in range(count + 1)}
    start: list[ir.Op] = []
    rungs: list[list[ir.Op]] = []
    current = start
    for op in scan:
        if isinstance(op, ir.Label) and op.name in labels:
            current = []
            rungs.append(current)
        else:
            current.append(op)
    assert len(rungs) == count + 1 and not rungs[-1], "a label for every rung and the end of the scan"
    return start, rungs[:-1]


def _walk(ops: list[ir.Op]):
    for op in ops:
        yield op
        if isinstance(op, ir.If):
            yield from _walk(op.then)
            yield from _walk(op.otherwise or [])


def _lines(gen: Gen, ops: list[ir.Op]) -> list[str]:
    gen.lines, gen.used, gen.depth = [], set(), 0
    emit_ops(gen, ops)
    return gen.lines


def _function(gen: Gen, name: str, start: list[str], body: list[str], load: list[str], store: list[str],
              timed: bool) -> list[str]:
    lines = [f"def {name}(S, n, t0, E):", *_indented(load, 1), "    done = 0", "    try:", "        while done < n:"]
    if timed:
        lines.append(f"            now = t0 + done * {gen.cycle_us}")
    lines += _indented(start + body or ["pass"], 3)
    lines += ["            done += 1", "    except Fault as fault:", "        fault.done = done", "        raise",
              "    finally:", *_indented(store or ["pass"], 2), "    return done"]
    return lines


def compile_program(program: Program, peripherals) -> Compiled:
    if program.settings.cycle_us <= 0:
        raise SimulationError([located(BAD_TIMER, "the cycle time must be positive to simulate", None)])
    problems = _unsupported(program)
    if problems:
        raise SimulationError(problems)
    placed = list(program.elements())
    elements = [element for _, element in placed]
    jumps = any(e.kind in JUMPS for e in elements)
    if jumps:
        _check_jumps(program, placed)
    try:
        code = lower_program(program, None, 1, SIMULATOR, trace=True)
    except lowering.LoweringError as problem:
        raise SimulationError([located(LOWERING_CODES[problem.kind], problem.message, problem.element)]) from None
    gen = Gen(program)
    gen.namespace.update(PER=peripherals, U=peripherals.uart)
    # a slot's cell is made when a chunk first uses it
    cells: dict[int, CellType] | None = defaultdict(CellType) if len(elements) > SINGLE_ELEMENTS else None
    # the two variants share one Gen, so that they number the slots alike
    writers = [_generate(gen, code, "run", False, cells, jumps), _generate(gen, code, "run_traced", True, cells, jumps)]
    _initial_values(gen, code, elements)
    if cells is not None:
        _sync(gen, cells)
    run, run_traced = (writer.function() for writer in writers)
    sends = any(isinstance(op, ir.UartSend) for op in _walk(code.scan))
    return Compiled(program, gen.slots, gen.index, gen.elements, run, run_traced, sends)
