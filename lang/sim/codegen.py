"""The code generator's working state: the Python source being written, the
storage slots it uses, and the registry of per-instruction generators.

Every program name and every piece of per-element memory (edge bits, timer
phases, a string's position) is a slot; the generated scan function keeps
each slot in a local variable (`v12`) for speed and reads/writes them all
back to the state list around a batch of scans (a large program, compiled
in chunks, keeps them in closure cells instead, filled and copied back the
same way).
"""

from __future__ import annotations

import re
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .. import storage
from ..instructions import JUMPS
from ..model import Element
from ..numbers import wrap, wrap_expr
from ..values import is_literal, literal_value
from .errors import BAD_OPERAND, BAD_TIMER, Fault, SimulationError, located

if TYPE_CHECKING:
    from .compile import JumpTable

DEFAULT_SIZE = 2


@dataclass
class Slot:
    key: str  # a program name, "$..." for LDmicro's hidden names, "~r.e.what" for element memory
    kind: str  # "bit" or "int"
    size: int  # bytes, for ints
    init: int  # a bit's is a bool


GENERATORS: dict[str, Callable] = {}


def handles(*kinds: str):
    """Register a generator `fn(gen, element, power)` for instruction kinds.
    It writes the element's code, which may reassign the power variable."""

    def register(fn):
        for kind in kinds:
            GENERATORS[kind] = fn
        return fn

    return register


class CannotSimulate(Exception):
    """An element the simulator cannot turn into code, reported as an LD6xx
    diagnostic when the Simulator is built (compiler.errors.CompileError is the compiler's)."""

    def __init__(self, code: str, message: str):
        super().__init__(message)
        self.code = code
        self.message = message


class Gen:
    def __init__(self, program, sizes: dict[str, int], bit_names: set[str]):
        self.program = program
        self.cycle_us = program.settings.cycle_us
        self.sizes = sizes
        self.bit_names = bit_names
        self.slots: list[Slot] = []
        self.index: dict[str, int] = {}
        self.lines: list[str] = []
        self.used: set[int] = set()  # the slots the lines written so far use: a chunk's cells
        self.depth = 0
        self.namespace: dict[str, object] = {"Fault": Fault}
        self.elements: list[tuple[int, int, Element]] = []
        self.element: Element | None = None
        self.number = -1  # the current element's number
        self.rung = -1
        self.position = -1  # the current element's index in its rung
        self.temp_count = 0
        self.uses_time = False
        self.traced = False
        self.jumps: JumpTable | None = None  # set by the compiler when the program jumps
        self.calling = False  # whether the rung being written holds a GOSUB
        self.counter_defs: dict[str, Element] = {}  # counter name -> the element RES takes its start from
        self.eeprom_next = 0  # the next PERSIST variable's EEPROM address

    # --- source ---------------------------------------------------------------

    def emit(self, line: str) -> None:
        self.lines.append("    " * self.depth + line)

    @contextmanager
    def block(self, header: str):
        self.emit(header)
        self.depth += 1
        yield
        self.depth -= 1

    def temp(self, prefix: str = "t") -> str:
        self.temp_count += 1
        return f"{prefix}{self.temp_count}"

    def constant(self, value: object, prefix: str = "K") -> str:
        """A name in the generated module's namespace bound to `value`."""
        name = f"{prefix}{self.number}_{len(self.namespace)}"
        self.namespace[name] = value
        return name

    # --- storage --------------------------------------------------------------

    def slot(self, key: str, kind: str, size: int = DEFAULT_SIZE, init: int | None = None) -> str:
        if key not in self.index:
            if init is None:
                init = False if kind == "bit" else 0
            self.index[key] = len(self.slots)
            self.slots.append(Slot(key, kind, size, init))
        self.used.add(self.index[key])
        return f"v{self.index[key]}"

    def var(self, name: str) -> str:
        """The local holding a program name (bit or integer)."""
        if name in self.bit_names:
            return self.slot(name, "bit")
        return self.slot(name, "int", self.size(name))

    def bit(self, name: str) -> str:
        return self.slot(name, "bit")

    def memory(self, what: str, kind: str = "bit", size: int = 4, init: int | None = None) -> str:
        """Per-element hidden state, keyed by the element's place so that a
        reloaded program keeps it where the element is unchanged."""
        assert self.element is not None, "element memory outside an element's code"
        key = f"~{self.rung}.{self.position}.{self.element.kind}.{what}"
        return self.slot(key, kind, size, init)

    def jump_table(self) -> JumpTable:
        """The table of a program that jumps (its GOTO, GOSUB and SUBPROG are written with it)."""
        assert self.jumps is not None, "a jump in a program the compiler found none in"
        return self.jumps

    def size(self, name: str) -> int:
        return self.sizes.get(name, DEFAULT_SIZE)

    # --- operands ---------------------------------------------------------------

    def arg(self, field: str):
        element = self.element
        assert element is not None, "an operand read outside an element's code"
        return element.args.get(field, element.spec.get_field(field).default)

    def literal(self, token: str) -> int:
        try:
            return literal_value(token)
        except ValueError as bad:
            raise CannotSimulate(BAD_OPERAND, str(bad)) from None

    def operand(self, token) -> str:
        """Python source reading an operand: a literal's value or a variable."""
        token = str(token)
        if is_literal(token):
            return str(self.literal(token))
        return self.var(token)

    def operand_size(self, token, default: int) -> int:
        token = str(token)
        return default if is_literal(token) else self.size(token)

    def dest(self, field: str = "dest") -> tuple[str, str]:
        """(local, name) of a destination, which must not be a literal."""
        name = str(self.arg(field))
        if is_literal(name):
            raise CannotSimulate(BAD_OPERAND, f"'{name}' is not a valid destination")
        return self.var(name), name

    def wrap(self, expr: str, name: str) -> str:
        if name in self.bit_names:
            return expr
        if re.fullmatch(r"-?\d+", expr):
            return str(wrap(int(expr), self.size(name)))
        return wrap_expr(expr, self.size(name))

    def fault(self, code: str, message_expr: str) -> str:
        """A statement raising a located run-time fault; the message is a
        Python expression (an f-string may show the values involved)."""
        return f"raise Fault({self.number}, {code!r}, {message_expr})"

    # --- elements -----------------------------------------------------------------

    def generate(self, element: Element, power: str) -> None:
        self.element = element
        self.position += 1
        self.number = len(self.elements)
        self.elements.append((self.rung, self.position, element))
        # a jump leaves the element's code at once: note its power before
        jumps = element.kind in JUMPS
        if self.traced and jumps:
            self.emit(f"E[{self.number}] = bool({power})")
        try:
            GENERATORS[element.kind](self, element, power)
        except CannotSimulate as problem:
            raise SimulationError([located(problem.code, problem.message, element)]) from None
        if self.traced and not jumps:
            self.emit(f"E[{self.number}] = bool({power})")


def timer_period(gen: Gen, delay: int, adjust: int, name: str) -> int:
    """LDmicro's period in scans (lang/storage.py), a problem with it a located error."""
    try:
        return storage.timer_period(gen.cycle_us, delay, adjust, name)
    except storage.TimerError as problem:
        raise CannotSimulate(BAD_TIMER, str(problem)) from None
