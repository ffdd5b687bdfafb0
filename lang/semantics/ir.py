"""The intermediate code: what one scan of a ladder program does, in terms a
back end translates op by op.

Storage is named. A `Bit` is an input pin, an output latch, a relay or hidden
element memory, or a temporary power bit of the rung being evaluated (its
class is in `Code.bits`). A `Var` is a signed integer of 1 to 4 bytes; a
`Byte` is one unsigned byte of a variable. Integer results are truncated to
their destination; operands are read as the signed values they hold
(docs/semantics.md, "Variable sizes"), so an op computes in the widest size
its operands and destination need.

The lowering (`lang.semantics.lower`) writes structured code: an element's
conditionals are `If` blocks, and the program's jumps (GOTO, GOSUB, RETURN)
go to the labels that start its rungs. The simulator turns that code into
Python as it is; the compiler first makes it a flat list with labels, jumps
and conditional jumps (`flatten`), which its optimiser rewrites and its back
ends translate.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..model import Element


@dataclass(frozen=True)
class Bit:
    name: str


@dataclass(frozen=True)
class Var:
    name: str
    size: int


@dataclass(frozen=True)
class Byte:
    """Byte `index` (0 = least significant) of a variable, read unsigned."""

    var: Var
    index: int

    @property
    def size(self) -> int:
        return 1


@dataclass(frozen=True)
class Const:
    value: int


Operand = Var | Byte | Const
Place = Var | Byte  # what an op writes (an integer variable or one byte of one)

# bit classes
INPUT, OUTPUT, MEMORY, TEMP = "input", "output", "memory", "temp"

NEGATED = {"==": "!=", "!=": "==", "<": ">=", ">=": "<", ">": "<=", "<=": ">"}


class Op:
    """An operation; `reads()`/`writes()` name the bits it uses, for the
    optimiser's dataflow."""

    def reads(self) -> tuple[Bit, ...]:
        return ()

    def writes(self) -> tuple[Bit, ...]:
        return ()


# --- program structure -------------------------------------------------------

@dataclass
class Label(Op):
    name: str


@dataclass
class Note(Op):
    """Text for the listing (the rung and element the code below is for);
    `rung` marks the start of a rung's code (its index in the program),
    `element` the start of an element's (the ladder element itself, which
    the simulator reports faults and energized state on)."""

    text: str
    rung: int | None = None
    element: Element | None = field(default=None, compare=False)


@dataclass
class Trace(Op):
    """The element whose code this follows (or, for a jump, precedes) has
    `bit` as its output power: the simulator records it for the editor.
    Only a lowering asked to trace writes it."""

    bit: Bit

    def reads(self):
        return (self.bit,)


@dataclass
class Jump(Op):
    target: str


@dataclass
class JumpIfBit(Op):
    bit: Bit
    value: bool
    target: str

    def reads(self):
        return (self.bit,)


@dataclass
class JumpIf(Op):
    """Jump when `a rel b` holds, comparing the signed values."""

    a: Operand
    rel: str
    b: Operand
    target: str


@dataclass
class JumpIfBitOf(Op):
    """Jump when bit `index` of `a` equals `value`: an index below 0 reads
    0, one at or past the width reads the sign bit (the value is signed)."""

    a: Operand
    index: Operand
    value: bool
    target: str


@dataclass
class Call(Op):
    """A subroutine call; `keep` are the temporary bits still needed after
    it, which the callee's rungs must not clobber (the optimiser fills it)."""

    target: str
    keep: frozenset = frozenset()


# the ops that go on at their `target` label (a Call has one too, but comes back)
JUMPS = (Jump, JumpIfBit, JumpIf, JumpIfBitOf)


@dataclass
class Return(Op):
    pass


# --- structured conditionals ----------------------------------------------------------

@dataclass(frozen=True)
class IsSet:
    bit: Bit
    value: bool = True


@dataclass(frozen=True)
class Holds:
    """`a rel b`, comparing the signed values."""

    a: Operand
    rel: str
    b: Operand


@dataclass(frozen=True)
class BitOf:
    """Bit `index` of `a` equals `value` (an index below 0 reads 0, one at or
    past the width the sign bit)."""

    a: Operand
    index: Operand
    value: bool


Condition = IsSet | Holds | BitOf


@dataclass
class If(Op):
    """`then` when `cond` holds, else `otherwise` (None: no else part). The
    labels, chosen when the lowering wrote it, are the flat form's."""

    cond: Condition
    then: list[Op]
    otherwise: list[Op] | None
    else_label: str
    end_label: str


def flatten(ops: list[Op]) -> list[Op]:
    """The flat form of structured code: each If becomes a conditional jump
    over its `then` part to its else label."""
    flat: list[Op] = []
    _flatten_into(flat, ops)
    return flat


def _flatten_into(flat: list[Op], ops: list[Op]) -> None:
    for op in ops:
        if not isinstance(op, If):
            flat.append(op)
            continue
        flat.append(_jump_unless(op.cond, op.else_label))
        _flatten_into(flat, op.then)
        if op.otherwise is not None:
            flat += [Jump(op.end_label), Label(op.else_label)]
            _flatten_into(flat, op.otherwise)
        else:
            flat.append(Label(op.else_label))
        flat.append(Label(op.end_label))


def _jump_unless(cond: Condition, target: str) -> Op:
    if isinstance(cond, IsSet):
        return JumpIfBit(cond.bit, not cond.value, target)
    if isinstance(cond, Holds):
        return JumpIf(cond.a, NEGATED[cond.rel], cond.b, target)
    return JumpIfBitOf(cond.a, cond.index, not cond.value, target)


# --- bits ----------------------------------------------------------------------

@dataclass
class SetBit(Op):
    dst: Bit
    value: bool

    def writes(self):
        return (self.dst,)


@dataclass
class CopyBit(Op):
    dst: Bit
    src: Bit
    invert: bool = False

    def reads(self):
        return (self.src,)

    def writes(self):
        return (self.dst,)


@dataclass
class AndBit(Op):
    """dst = dst and (src, or not src when inverted)"""

    dst: Bit
    src: Bit
    invert: bool = False

    def reads(self):
        return (self.dst, self.src)

    def writes(self):
        return (self.dst,)


@dataclass
class OrBit(Op):
    dst: Bit
    src: Bit

    def reads(self):
        return (self.dst, self.src)

    def writes(self):
        return (self.dst,)


# --- integers ----------------------------------------------------------------------

@dataclass
class Move(Op):
    dst: Place
    src: Operand


@dataclass
class Arith(Op):
    """add, sub, mul, and, or, xor; `overflow` is set (never cleared) when an
    add or sub does not fit the destination."""

    op: str
    dst: Place
    a: Operand
    b: Operand
    overflow: Bit | None = None

    def writes(self):
        return (self.overflow,) if self.overflow else ()


@dataclass
class ChangeBitOf(Op):
    """Set or clear bit `index` of dst; an index outside 0..8*size-1 changes
    nothing."""

    dst: Place
    index: Operand
    value: bool


@dataclass
class Divide(Op):
    """div (truncating toward zero) or mod (the dividend's sign); a div may
    also store the remainder, from the same division. The result of a
    division by zero is left to the back end."""

    op: str
    dst: Place
    a: Operand
    b: Operand
    remainder: Place | None = None


@dataclass
class Unary(Op):
    op: str  # neg, not
    dst: Place
    a: Operand


@dataclass
class Shift(Op):
    """shl, shr (arithmetic), sr0 (logical), rol, ror of `a` within `width`
    bytes by `count` bits (negative: none; past the width: all out or round)."""

    op: str
    dst: Place
    a: Operand
    count: Operand
    width: int


@dataclass
class Convert(Op):
    """bin2bcd, bcd2bin, swap, opposite of `src` within `width` bytes."""

    op: str
    dst: Place
    src: Operand
    width: int


@dataclass
class Table(Op):
    """dst = values[index]; the index must be in range (the front end or the
    program guarantees it)."""

    dst: Place
    values: tuple[int, ...]
    index: Operand


@dataclass
class Permute(Op):
    """BUS: dst = the byte with bit d set for each (s, d) of `pairs` whose
    source bit s is set in src (a bit past src's width is its sign bit)."""

    dst: Place
    src: Operand
    pairs: tuple[tuple[int, int], ...]


# --- peripherals and the machine -------------------------------------------------------

@dataclass
class ReadAdc(Op):
    dst: Var
    channel: int
    refs: int


@dataclass
class SetPwm(Op):
    """Drive output `unit` (OC0A...) at `freq` Hz with `duty` out of `full`
    (100 for percent, 256/512/1024 for the other resolutions)."""

    unit: str
    duty: Operand
    full: int
    freq: int


@dataclass
class PwmOff(Op):
    unit: str


@dataclass
class UartSend(Op):
    """Send the low byte; without `wait` it is lost while the transmitter is
    busy, with `wait` the MCU waits for the transmitter first."""

    value: Operand
    wait: bool = False


@dataclass
class UartReady(Op):
    dst: Bit

    def writes(self):
        return (self.dst,)


@dataclass
class UartAvailable(Op):
    dst: Bit

    def writes(self):
        return (self.dst,)


@dataclass
class UartTake(Op):
    """dst = the next received byte; with `wait` it may not have come yet
    (the MCU waits for it), without it the receiver was seen holding it."""

    dst: Place
    wait: bool = False


@dataclass
class ReadSfr(Op):
    """dst = the byte at data address `address` (a constant, or a variable's
    value modulo 65536), read unsigned: LDmicro's raw register access."""

    dst: Place
    address: Operand


@dataclass
class WriteSfr(Op):
    """The low byte of `value` to data address `address` (as ReadSfr's)."""

    address: Operand
    value: Operand


@dataclass
class EepromLoad(Op):
    var: Var
    address: int


@dataclass
class EepromSave(Op):
    """Bring the EEPROM copy at `address` towards `var`: a byte that differs
    is written when the EEPROM is idle (one byte per scan at most)."""

    var: Var
    address: int


@dataclass
class Delay(Op):
    """Busy-wait: `amount` microseconds (a constant), or `amount` loops of
    the back end's `delay_loop_cycles` CPU cycles (a variable; T2DLY
    converted the time with that figure)."""

    amount: Operand
    loops: bool


@dataclass
class ClearWatchdog(Op):
    pass


@dataclass
class Halt(Op):
    """Loop forever (LOCK); the watchdog resets the MCU."""


@dataclass
class Sleep(Op):
    pass


@dataclass
class Code:
    """A lowered program: the scan, what runs once before the first scan,
    and the storage both use."""

    scan: list[Op]
    init: list[Op]
    bits: dict[str, str]  # bit name -> INPUT, OUTPUT, MEMORY or TEMP
    vars: dict[str, int]  # variable name -> size in bytes
    eeprom: int = 0  # EEPROM bytes PERSIST uses
