"""The simulator back end's working state: the Python source being written,
the storage slots it uses, and where in the program it is.

Every program name and every element memory (edge bits, timer phases, a
string's position) is a slot; the generated scan function keeps each slot in
a local variable (`v12`) for speed and reads/writes them all back to the
state list around a batch of scans (a large program, compiled in chunks,
keeps them in closure cells instead, filled and copied back the same way).
The lowering's temporaries die with their rung: they are plain locals,
named afresh in each rung, so a chunk's frame holds its slots and little
more.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..model import Element, Program
from ..semantics import ir
from .errors import Fault

if TYPE_CHECKING:
    from .compile import JumpTable

# the lowering's names: element memories "~m<rung>.<position>.<what>",
# temporary bits "~t<n>" and integers "~v<n>"
MEMORY, TEMP_BIT, TEMP_VAR = "~m", "~t", "~v"


@dataclass
class Slot:
    key: str  # a program name, "$..." for LDmicro's hidden names, "~r.e.kind.what" for element memory
    kind: str  # "bit" or "int"
    size: int  # bytes, for ints
    init: int  # a bit's is a bool


class Gen:
    def __init__(self, program: Program):
        self.program = program
        self.cycle_us = program.settings.cycle_us
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
        self.temps: dict[str, str] = {}  # the rung's temporaries: lowering name -> local
        self.uses_time = False
        self.traced = False
        self.jumps: JumpTable | None = None  # set by the compiler when the program jumps
        self.calling = False  # whether the rung being written holds a GOSUB
        self.return_point: int | None = None  # the segment a GOSUB just written returns to
        self.counted: set[str] = set()  # variables below a limit they count up to, here

    # --- source ---------------------------------------------------------------

    def emit(self, line: str) -> None:
        self.lines.append("    " * self.depth + line)

    @contextmanager
    def block(self, header: str):
        self.emit(header)
        self.depth += 1
        yield
        self.depth -= 1

    def constant(self, value: object, prefix: str = "K") -> str:
        """A name in the generated module's namespace bound to `value`."""
        name = f"{prefix}{self.number}_{len(self.namespace)}"
        self.namespace[name] = value
        return name

    # --- storage --------------------------------------------------------------

    def slot(self, key: str, kind: str, size: int = 4, init: int | None = None) -> str:
        if key not in self.index:
            if init is None:
                init = False if kind == "bit" else 0
            self.index[key] = len(self.slots)
            self.slots.append(Slot(key, kind, size, init))
        self.used.add(self.index[key])
        return f"v{self.index[key]}"

    def new_rung(self, index: int, calling: bool) -> None:
        self.rung, self.position, self.temps, self.calling = index, -1, {}, calling

    def place(self, name: str, kind: str, size: int) -> str:
        """The Python name holding one of the lowering's bits or integers."""
        if name.startswith((TEMP_BIT, TEMP_VAR)):
            local = self.temps.get(name)
            if local is None:
                local = self.temps[name] = f"{'t' if kind == 'bit' else 'w'}{len(self.temps) + 1}"
            # after a GOSUB the rung goes on where it was, which may be in
            # another call of its chunk's function: such a rung keeps them in slots
            return self.slot(f"~{self.rung}.{local}", kind, size) if self.calling else local
        if name.startswith(MEMORY):
            # keyed by the element's place and kind, so that a reloaded
            # program keeps it where the element is unchanged
            assert self.element is not None, "element memory outside an element's code"
            rung_position, what = name[len(MEMORY):].rsplit(".", 1)
            return self.slot(f"~{rung_position}.{self.element.kind}.{what}", kind, size)
        return self.slot(name, kind, size)

    def bit(self, bit: ir.Bit) -> str:
        return self.place(bit.name, "bit", 1)

    def var(self, var: ir.Var) -> str:
        return self.place(var.name, "int", var.size)

    # --- elements -----------------------------------------------------------------

    def enter(self, element: Element) -> None:
        """The code that follows is `element`'s."""
        self.element = element
        self.position += 1
        self.number = len(self.elements)
        self.elements.append((self.rung, self.position, element))

    def fault(self, code: str, message_expr: str) -> str:
        """A statement raising a located run-time fault; the message is a
        Python expression (an f-string may show the values involved)."""
        return f"raise Fault({self.number}, {code!r}, {message_expr})"
