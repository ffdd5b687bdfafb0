"""The lowering's working state: the ops being written, fresh labels and
temporaries, element memories, operands, and structured conditionals
(`with b.if_(cond) as branch: ... with branch.otherwise(): ...`)."""

from __future__ import annotations

from collections.abc import Callable
from contextlib import contextmanager

from lang.model import Element
from lang.storage import DEFAULT_SIZE, TimerError, eeprom_layout, timer_period
from lang.values import is_literal, literal_value

from .. import ir
from ..errors import OPERAND, TIMER, fail
from ..ir import Condition, Holds, IsSet
from ..operands import bit_refusal

__all__ = ["LOWERINGS", "Builder", "Holds", "IsSet", "lowers"]

LOWERINGS: dict[str, Callable] = {}


def lowers(*kinds: str):
    """Register `fn(builder, element, power)` as the lowering of instruction kinds."""

    def register(fn):
        for kind in kinds:
            LOWERINGS[kind] = fn
        return fn

    return register


class Branch:
    """The else part of an `if_`: `with branch.otherwise(): ...`, the last
    thing inside the `if_` block."""

    def __init__(self, builder: Builder, node: ir.If):
        self.builder = builder
        self.node = node

    @contextmanager
    def otherwise(self):
        self.node.otherwise = []
        self.builder.blocks[-1] = self.node.otherwise
        yield


class Builder:
    def __init__(self, program, elements: list[Element], bits: set[str], sizes: dict[str, int],
                 classes: dict[str, str]):
        self.program = program
        self.cycle_us = program.settings.cycle_us
        self.bit_names = bits
        self.sizes = sizes
        self.classes = classes  # program bit name -> ir bit class
        self.ops: list[ir.Op] = []
        self.blocks = [self.ops]  # the innermost block being written last
        self.vars: dict[str, int] = {}
        self.bits: dict[str, str] = {}
        self.element: Element | None = None
        self.rung = -1
        self.position = -1
        self._labels = 0
        self._temps = 0
        self.eeprom = 0  # EEPROM bytes the PERSIST variables take so far
        # each PERSIST's (first address, address after it), laid out as the checks see it (LD705)
        persists = [e for e in elements if e.kind == "PERSIST"]
        places = eeprom_layout(persists, lambda name: (name in bits, sizes.get(name, DEFAULT_SIZE)))
        self.eeprom_places = {id(e): (first, end) for e, first, end in places}
        self.eeprom_size = 0  # the part's
        self.overflow_read = "ROverflowFlagV" in {
            str(e.args.get("name")) for e in elements if e.kind == "CONTACTS"}

    # --- writing ------------------------------------------------------------------

    def emit(self, op: ir.Op) -> None:
        self.blocks[-1].append(op)

    def new_label(self, hint: str = "L") -> str:
        self._labels += 1
        return f"{hint}{self._labels}"

    def place(self, label: str) -> None:
        self.emit(ir.Label(label))

    @contextmanager
    def if_(self, cond: Condition):
        """`with b.if_(cond) as branch:` then-part, optionally ending with
        `with branch.otherwise():` else-part."""
        node = ir.If(cond, [], None, self.new_label(), self.new_label())
        self.emit(node)
        self.blocks.append(node.then)
        yield Branch(self, node)
        self.blocks.pop()

    # --- storage --------------------------------------------------------------------

    def temp(self) -> ir.Bit:
        """A fresh temporary bit (power flow inside a rung)."""
        self._temps += 1
        name = f"~t{self._temps}"
        self.bits[name] = ir.TEMP
        return ir.Bit(name)

    def temp_var(self, size: int = 4) -> ir.Var:
        self._temps += 1
        name = f"~v{self._temps}"
        self.vars[name] = size
        return ir.Var(name, size)

    def bit(self, name: str) -> ir.Bit:
        self.bits[name] = self.classes.get(name, ir.MEMORY)
        return ir.Bit(name)

    def var(self, name: str) -> ir.Var:
        if name in self.bit_names:
            raise fail(OPERAND, bit_refusal(name), self.element)
        size = self.size(name)
        self.vars[name] = size
        return ir.Var(name, size)

    def size(self, name: str) -> int:
        return self.sizes.get(name, DEFAULT_SIZE)

    def memory_bit(self, what: str) -> ir.Bit:
        """Hidden per-element state (edge memories...), one per element instance."""
        name = f"~m{self.rung}.{self.position}.{what}"
        self.bits[name] = ir.MEMORY
        return ir.Bit(name)

    def memory_var(self, what: str, size: int = 4) -> ir.Var:
        name = f"~m{self.rung}.{self.position}.{what}"
        self.vars[name] = size
        return ir.Var(name, size)

    # --- operands ----------------------------------------------------------------------

    def arg(self, field: str):
        element = self.element
        assert element is not None, "an operand read outside an element's lowering"
        return element.args.get(field, element.spec.get_field(field).default)

    def literal(self, token) -> int:
        try:
            return literal_value(str(token))
        except ValueError as bad:
            raise fail(OPERAND, str(bad), self.element) from None

    def operand(self, token) -> ir.Var | ir.Const:
        token = str(token)
        if is_literal(token):
            return ir.Const(self.literal(token))
        return self.var(token)

    def dest(self, field: str = "dest") -> ir.Var:
        name = str(self.arg(field))
        if is_literal(name):
            raise fail(OPERAND, f"'{name}' is not a valid destination", self.element)
        return self.var(name)

    def period(self, delay: int, adjust: int, name: str) -> int:
        """A timer's period in scans, with LDmicro's checks."""
        try:
            return timer_period(self.program.settings.cycle_us, delay, adjust, name)
        except TimerError as problem:
            raise fail(TIMER, str(problem), self.element) from None
