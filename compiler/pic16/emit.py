"""Writing PIC instructions while tracking the bank and W: the PIC16 back
end's emitter, which the PIC18 back end shares with a `Core` of its own.

An instruction names a file register by the low bits of its address; the
bank selection supplies the rest (STATUS.RP1:RP0 on a PIC16, BSR on a PIC18).
The emitter selects the bank an operand needs just before the instruction,
and only when what is selected is not already known to be right. It also
knows what W holds (a constant, a copy of a RAM byte), so that the patterns
do not load it again.

Both are known along every path: a jump records what is known at its target,
a label keeps what every way in agrees on, and a label reached by a later
jump or by a call (a loop head, a subroutine) knows nothing. A skip
instruction (BTFSS...) is a branch over the next instruction, so that
instruction must not need a bank selection of its own: the patterns write
`skip, GOTO, body, label` and `compress_skips` turns a skip over a GOTO over
one instruction into a single skip when nothing else was needed.

The patterns speak the mid-range instruction set; a family's `Core` says
how its banks are selected and where its core registers are, and its
assembler writes each mnemonic as its own instruction (RLF is the PIC18's
RLCF).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Protocol

from ..image import LoopBound
from . import asm as a
from .part import Part

STATUS, PCL, FSR, PCLATH, INDF, INTCON = 0x03, 0x02, 0x04, 0x0A, 0x00, 0x0B
C, DC, Z, RP0, RP1, IRP = 0, 1, 2, 5, 6, 7  # STATUS bits (C, DC and Z: the same on every PIC16 and PIC18)
W, F = 0, 1  # destination of a byte operation

_SKIPS = frozenset(("btfsc", "btfss", "decfsz", "incfsz"))
_INVERSE = {"btfsc": "btfss", "btfss": "btfsc"}
# byte operations: they write W when d = 0, the file register when d = 1
_BYTE_OPS = frozenset(("addwf", "andwf", "comf", "decf", "decfsz", "incf", "incfsz", "iorwf", "movf", "rlf",
                       "rrf", "subwf", "swapf", "xorwf", "addwfc", "subwfb", "lslf", "lsrf", "asrf"))
# instructions whose first operand is a file register: its bank is selected first
_FILE_OPS = _BYTE_OPS | {"movwf", "clrf", "bcf", "bsf", "btfsc", "btfss", "mulwf"}
_LITERAL_OPS = frozenset(("addlw", "andlw", "iorlw", "movlw", "sublw", "xorlw", "retlw", "mullw"))
_FOLD = {"addlw": lambda w, k: w + k, "andlw": lambda w, k: w & k, "iorlw": lambda w, k: w | k,
         "sublw": lambda w, k: k - w, "xorlw": lambda w, k: w ^ k, "movlw": lambda w, k: k,
         "mullw": lambda w, k: w}


class Core(Protocol):
    """A family's bank selection and core registers, as the emitter needs
    them. The selection is a tuple of components (RP0 and RP1; BSR), each
    known or None."""

    status: int  # STATUS (C, DC and Z at bits 0, 1 and 2)
    fsr: int  # the indirect pointer's low byte
    indf: int  # the byte it points at
    unknown: tuple  # the selection where nothing is known (a component may keep its reset value)
    moves_far: bool  # MOVFF copies a byte between any two addresses, whatever the bank
    carry_ops: bool  # the patterns may use ADDWFC, SUBWFB, LSLF, LSRF and ASRF (the enhanced mid-range core)

    def unbanked(self, address: int) -> bool:
        """True when an instruction reaches the address whatever the bank."""
        ...

    def wanted(self, address: int) -> tuple:
        """The selection that reaches the address (None: a component that does not matter)."""
        ...

    def selection(self, component: int, value: int) -> tuple:
        """(mnemonic, operands) that set a component of the selection."""
        ...

    def effect(self, op: str, args: tuple) -> dict[int, int | None]:
        """The components an instruction that writes changes: component -> value, None when unknown."""
        ...

    def home(self, bank: int) -> int:
        """An address in the bank."""
        ...

    def pointer_high(self, high: int) -> list[tuple]:
        """The instructions (mnemonic, operands) that make the indirect pointer reach
        `high` * 256 and up; W may change."""
        ...


class MidRange:
    """The PIC16's: STATUS RP1:RP0 pick one of up to four banks of 128
    addresses; the core registers and the common RAM are in every bank; IRP
    is the indirect pointer's ninth bit."""

    status, fsr, indf = STATUS, FSR, INDF
    moves_far = False
    carry_ops = False
    # core registers that every bank maps to the same register
    _UNBANKED = frozenset((INDF, PCL, STATUS, FSR, PCLATH, INTCON))

    def __init__(self, part: Part, high_banks: bool = True):
        self.part = part
        self._common = frozenset(part.common or ())
        # without anything in banks 2 and 3, RP1 keeps its reset value 0
        self.unknown = (None, None) if high_banks or part.banks <= 2 else (None, 0)

    def unbanked(self, address: int) -> bool:
        return (address & 0x7F) in self._UNBANKED or address in self._common

    def wanted(self, address: int) -> tuple:
        bank = address >> 7
        return bank & 1, (bank >> 1 if self.part.banks > 2 else None)

    def selection(self, component: int, value: int) -> tuple:
        return "bsf" if value else "bcf", (STATUS, (RP0, RP1)[component])

    def effect(self, op: str, args: tuple) -> dict[int, int | None]:
        if not args or args[0] != STATUS:
            return {}
        if op in ("bcf", "bsf"):
            return {(RP0, RP1).index(args[1]): int(op == "bsf")} if args[1] in (RP0, RP1) else {}
        return {0: None, 1: None}

    def home(self, bank: int) -> int:
        return bank << 7 | 0x20

    def pointer_high(self, high: int) -> list[tuple]:
        return [("bsf" if high else "bcf", (STATUS, IRP))]


@dataclass(frozen=True)
class State:
    bank: tuple = ()  # the bank selection, per component (None: not known)
    w: frozenset = frozenset()  # facts: ("const", byte) or ("mem", address)

    def meet(self, other: State) -> State:
        return State(tuple(x if x == y else None for x, y in zip(self.bank, other.bank)), self.w & other.w)


class Emitter:
    def __init__(self, assembler: a.Writer, part: Part, ram: frozenset[int], core: Core):
        self.asm = assembler
        self.part = part
        self.core = core
        self.ram = ram  # bytes only the program changes: W may be known to hold one
        self.unknown = State(core.unknown)
        self.state: State | None = self.unknown  # None: this point is unreachable
        self._entry: dict[str, tuple] = {}  # loop heads entered with a known bank -> that selection
        self._incoming: dict[str, list[State]] = {}
        self._skipped: State | None = None  # the state before the instruction a skip may skip
        self._labels = 0
        self._loops: set[str] = set()
        self._placed: set[str] = set()
        self.bounds: dict[str, LoopBound] = {}  # loop heads and their bounds, for the scan-time budget

    @property
    def status(self) -> int:
        return self.core.status

    @property
    def fsr(self) -> int:
        return self.core.fsr

    @property
    def indf(self) -> int:
        return self.core.indf

    # --- labels and control flow ------------------------------------------------

    def new_label(self, hint: str = "L") -> str:
        self._labels += 1
        return f"_{hint}{self._labels}"

    def _merge_skip(self) -> None:
        pending, self._skipped = self._skipped, None
        if pending is not None:
            self.state = pending if self.state is None else self.state.meet(pending)

    def _record(self, target: str) -> None:
        assert target not in self._placed or target in self._loops, f"backward jump to {target}"
        if self.state is not None:
            self._incoming.setdefault(target, []).append(self.state)

    def label(self, name: str, loop: bool = False, bound: LoopBound | None = None, bank: int | None = None) -> None:
        """A label; `loop`: later code may jump back to it (or call it), so
        nothing is known there; a loop head gives its `bound`, and `bank`
        when every way in selects that bank (the jumps back select it)."""
        self._merge_skip()
        if bound is not None:
            self.bounds[name] = bound
        if bank is not None:
            self.select(self.core.home(bank))
            self._entry[name] = self.core.wanted(self.core.home(bank))
        self._placed.add(name)
        if loop:
            self._loops.add(name)
        states = self._incoming.pop(name, []) + ([self.state] if self.state is not None else [])
        if name in self._entry:
            self.state = State(self._entry[name])
        elif loop or not states:
            self.state = self.unknown
        else:
            merged = states[0]
            for other in states[1:]:
                merged = merged.meet(other)
            self.state = merged
        self.asm.label(name)

    def goto(self, target: str) -> None:
        bank = self._entry.get(target)
        if bank is not None and self.state is not None and self.state.bank != bank:
            self._select(bank)
        pending, self._skipped = self._skipped, None
        self._record(target)
        self.asm.goto(target)
        self.state = pending  # reached only when a skip skipped the GOTO

    def call(self, target: str) -> None:
        """A call: the callee may leave any bank selected and anything in W."""
        pending, self._skipped = self._skipped, None
        self.asm.call(target)
        self.state = self.unknown if self.state is not None or pending is not None else None

    def end_path(self) -> None:
        """After RETURN or an endless loop: nothing falls through."""
        self._merge_skip()
        self.state = None

    def comment(self, text: str) -> None:
        self.asm.comment(text)

    # --- banks ----------------------------------------------------------------------------

    def reaches(self, address: int) -> bool:
        """True when an instruction reaches `address` whatever the bank."""
        return self.core.unbanked(address)

    def needs_bank(self, address: int) -> bool:
        """True when reaching `address` would need a bank selection now."""
        if self.state is None or self.reaches(address):
            return False
        return any(want is not None and have != want for have, want in zip(self.state.bank, self.core.wanted(address)))

    def select(self, address: int) -> None:
        """Select the bank of `address` if it is not selected."""
        if self.state is None or self.reaches(address):
            return
        assert self._skipped is None or not self.needs_bank(address), "a bank selection would be skipped"
        self._select(self.core.wanted(address))

    def _select(self, wanted: tuple) -> None:
        assert self.state is not None
        for component, want in enumerate(wanted):
            if want is not None and self.state.bank[component] != want:
                op, args = self.core.selection(component, want)
                self._emit(op, *args)
                self.state = replace(self.state, bank=self.state.bank[:component] + (want,)
                                     + self.state.bank[component + 1:])

    def point_high(self, high: int) -> None:
        """The indirect pointer reaches `high` * 256 and up (W may change)."""
        for op, args in self.core.pointer_high(high):
            self.ins(op, *args)

    def bank0(self) -> None:
        """Bank 0 selected (what code outside the patterns expects after a
        call that leaves it unknown)."""
        self.select(0x20)

    # --- instructions ------------------------------------------------------------------------

    def _emit(self, op: str, *args: int, comment: str = "") -> None:
        self.asm.emit(op, *args, comment=comment)

    def ins(self, op: str, *args: int, comment: str = "") -> None:
        """An instruction; a file operand's bank is selected first."""
        if op in _FILE_OPS:
            self.select(args[0])
        pending, self._skipped = self._skipped, None
        self._emit(op, *args, comment=comment)
        if self.state is not None:
            self.state = self._effect(self.state, op, args)
        if pending is not None:
            self.state = pending if self.state is None else self.state.meet(pending)
        if op in _SKIPS and self.state is not None:
            self._skipped = self.state

    def _effect(self, state: State, op: str, args: tuple) -> State:
        w = state.w
        if op in _LITERAL_OPS:
            values = [v for kind, v in w if kind == "const"]
            if op == "movlw":
                w = frozenset({("const", args[0] & 0xFF)})
            elif values:
                w = frozenset({("const", _FOLD[op](values[0], args[0]) & 0xFF)})
            else:
                w = frozenset()
        elif op == "clrw":
            w = frozenset({("const", 0)})
        elif op in _BYTE_OPS and args[1] == W:
            ram = self._is_ram(args[0])
            w = frozenset({("mem", args[0])}) if op == "movf" and ram else frozenset()
        elif op in ("movwf", "clrf", "bcf", "bsf", "movff") or op in _BYTE_OPS:
            address = args[1] if op == "movff" else args[0]
            # facts about the byte written; all of them when it is written indirectly
            w = frozenset(f for f in w if f[0] == "const" or (f[1] != address and address != self.core.indf))
            if op == "movwf" and self._is_ram(address):
                w = w | {("mem", address)}
        reads = op in _LITERAL_OPS or op in ("btfsc", "btfss") or (op in _BYTE_OPS and args[1] == W)
        changed = {} if reads else self.core.effect(op, args)
        return State(tuple(changed.get(i, value) for i, value in enumerate(state.bank)), w)

    def _is_ram(self, address: int) -> bool:
        return address in self.ram

    def note_w(self, fact: tuple) -> None:
        """W now holds `fact` (only after an instruction no skip guards)."""
        if self.state is not None and self._skipped is None:
            self.state = replace(self.state, w=self.state.w | {fact})

    def forget_w(self) -> None:
        if self.state is not None:
            self.state = replace(self.state, w=frozenset())

    # --- W --------------------------------------------------------------------------------------

    def w_holds(self, fact: tuple) -> bool:
        return self.state is not None and self._skipped is None and fact in self.state.w

    def load_constant(self, value: int) -> None:
        """W = a byte constant."""
        value &= 0xFF
        if not self.w_holds(("const", value)):
            self.ins("movlw", value)

    def load(self, address: int) -> None:
        """W = a file register (read afresh unless it is RAM W already holds)."""
        if not self.w_holds(("mem", address)):
            self.ins("movf", address, W)

    def store(self, address: int) -> None:
        """The file register = W."""
        self.ins("movwf", address)

    def copy(self, source: int, target: int) -> None:
        """A file register = another: through W, or with MOVFF where a bank
        selection would be needed (two words, two cycles, no bank, W kept)."""
        if self.core.moves_far and not self.w_holds(("mem", source)) and (
                self.needs_bank(source) or self.needs_bank(target)):
            self.ins("movff", source, target)
            return
        self.load(source)
        self.store(target)


def compress_skips(items: list) -> None:
    """`BTFSx f,b; GOTO L; one instruction; L:` -> `BTFSy f,b; the instruction`."""
    i = 0
    while i + 3 < len(items):
        skip, jump, body, label = items[i:i + 4]
        if (isinstance(skip, a.Ins) and skip.op in _INVERSE and isinstance(jump, a.Goto) and not jump.call
                and isinstance(body, a.Ins) and isinstance(label, a.Label) and label.name == jump.target):
            items[i:i + 2] = [a.Ins(_INVERSE[skip.op], skip.args, skip.comment)]
        i += 1
