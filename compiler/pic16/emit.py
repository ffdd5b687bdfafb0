"""Writing PIC16 instructions while tracking the bank and W.

An instruction names a file register by the low 7 bits of its address;
STATUS.RP1:RP0 select the bank. The emitter selects the bank an operand needs
just before the instruction, and only when what is selected is not already
known to be right. It also knows what W holds (a constant, a copy of a RAM
byte), so that the patterns do not load it again.

Both are known along every path: a jump records what is known at its target,
a label keeps what every way in agrees on, and a label reached by a later
jump or by a call (a loop head, a subroutine) knows nothing. A skip
instruction (BTFSS...) is a branch over the next instruction, so that
instruction must not need a bank selection of its own: the patterns write
`skip, GOTO, body, label` and `compress_skips` turns a skip over a GOTO over
one instruction into a single skip when nothing else was needed.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ..image import LoopBound
from . import asm as a
from .part import Part

STATUS, PCL, FSR, PCLATH, INDF, INTCON = 0x03, 0x02, 0x04, 0x0A, 0x00, 0x0B
C, DC, Z, RP0, RP1, IRP = 0, 1, 2, 5, 6, 7  # STATUS bits (the same on every mid-range part)
W, F = 0, 1  # destination of a byte operation

# core registers that every bank maps to the same register
_UNBANKED = frozenset((INDF, PCL, STATUS, FSR, PCLATH, INTCON))

_SKIPS = frozenset(("btfsc", "btfss", "decfsz", "incfsz"))
_INVERSE = {"btfsc": "btfss", "btfss": "btfsc"}
# byte operations: they write W when d = 0, the file register when d = 1
_BYTE_OPS = frozenset(("addwf", "andwf", "comf", "decf", "decfsz", "incf", "incfsz", "iorwf", "movf", "rlf",
                       "rrf", "subwf", "swapf", "xorwf"))
_LITERAL_OPS = frozenset(("addlw", "andlw", "iorlw", "movlw", "sublw", "xorlw", "retlw"))
_FOLD = {"addlw": lambda w, k: w + k, "andlw": lambda w, k: w & k, "iorlw": lambda w, k: w | k,
         "sublw": lambda w, k: k - w, "xorlw": lambda w, k: w ^ k, "movlw": lambda w, k: k}


@dataclass(frozen=True)
class State:
    rp0: int | None = None
    rp1: int | None = None
    w: frozenset = frozenset()  # facts: ("const", byte) or ("mem", address)

    def meet(self, other: State) -> State:
        return State(self.rp0 if self.rp0 == other.rp0 else None, self.rp1 if self.rp1 == other.rp1 else None,
                     self.w & other.w)


UNKNOWN = State()


class Emitter:
    def __init__(self, assembler: a.Assembler, part: Part, ram: frozenset[int], high_banks: bool = True):
        self.asm = assembler
        self.part = part
        self.ram = ram  # bytes only the program changes: W may be known to hold one
        # without anything in banks 2 and 3, RP1 keeps its reset value 0
        self.unknown = UNKNOWN if high_banks or part.banks <= 2 else State(rp1=0)
        self.state: State | None = self.unknown  # None: this point is unreachable
        self._entry: dict[str, int] = {}  # loop heads entered with a known bank -> that bank
        self._common = frozenset(part.common or ())
        self._incoming: dict[str, list[State]] = {}
        self._skipped: State | None = None  # the state before the instruction a skip may skip
        self._labels = 0
        self._loops: set[str] = set()
        self._placed: set[str] = set()
        self.bounds: dict[str, LoopBound] = {}  # loop heads and their bounds, for the scan-time budget

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
            self.select(bank << 7 | 0x20)
            self._entry[name] = bank
        self._placed.add(name)
        if loop:
            self._loops.add(name)
        states = self._incoming.pop(name, []) + ([self.state] if self.state is not None else [])
        if name in self._entry:
            self.state = State(self._entry[name] & 1, self._entry[name] >> 1)
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
        if bank is not None and self.state is not None and (self.state.rp0, self.state.rp1) != (bank & 1, bank >> 1):
            self.select(bank << 7 | 0x20)
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
        return (address & 0x7F) in _UNBANKED or address in self._common

    def needs_bank(self, address: int) -> bool:
        """True when reaching `address` would need a bank selection now."""
        if self.state is None or self.reaches(address):
            return False
        bank = address >> 7
        return self.state.rp0 != bank & 1 or (self.part.banks > 2 and self.state.rp1 != bank >> 1)

    def select(self, address: int) -> None:
        """Select the bank of `address` if it is not selected."""
        if self.state is None or self.reaches(address):
            return
        bank = address >> 7
        assert self._skipped is None or not self.needs_bank(address), "a bank selection would be skipped"
        if self.state.rp0 != bank & 1:
            self._emit("bsf" if bank & 1 else "bcf", STATUS, RP0)
            self.state = replace(self.state, rp0=bank & 1)
        if self.part.banks > 2 and self.state.rp1 != bank >> 1:
            self._emit("bsf" if bank >> 1 else "bcf", STATUS, RP1)
            self.state = replace(self.state, rp1=bank >> 1)

    def bank0(self) -> None:
        """Bank 0 selected (what code outside the patterns expects after a
        call that leaves it unknown)."""
        self.select(0x20)

    # --- instructions ------------------------------------------------------------------------

    def _emit(self, op: str, *args: int, comment: str = "") -> None:
        self.asm.emit(op, *args, comment=comment)

    def ins(self, op: str, *args: int, comment: str = "") -> None:
        """An instruction; a file operand's bank is selected first."""
        if op in _BYTE_OPS or op in ("movwf", "clrf", "bcf", "bsf", "btfsc", "btfss"):
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
        elif op in ("movwf", "clrf") or (op in _BYTE_OPS and args[1] == F) or op in ("bcf", "bsf"):
            address = args[0]
            # facts about the byte written; all of them when it is written indirectly
            w = frozenset(f for f in w if f[0] == "const" or (f[1] != address and address != INDF))
            if op == "movwf" and self._is_ram(address):
                w = w | {("mem", address)}
            if address == STATUS and op in ("bcf", "bsf") and args[1] in (RP0, RP1):
                value = 1 if op == "bsf" else 0
                return replace(state, w=w, **({"rp0": value} if args[1] == RP0 else {"rp1": value}))
            if address == STATUS and op not in ("bcf", "bsf"):
                return State(w=w)
        return replace(state, w=w)

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


def compress_skips(items: list) -> None:
    """`BTFSx f,b; GOTO L; one instruction; L:` -> `BTFSy f,b; the instruction`."""
    i = 0
    while i + 3 < len(items):
        skip, jump, body, label = items[i:i + 4]
        if (isinstance(skip, a.Ins) and skip.op in _INVERSE and isinstance(jump, a.Goto) and not jump.call
                and isinstance(body, a.Ins) and isinstance(label, a.Label) and label.name == jump.target):
            items[i:i + 2] = [a.Ins(_INVERSE[skip.op], skip.args, skip.comment)]
        i += 1
