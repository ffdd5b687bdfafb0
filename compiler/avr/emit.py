"""Writing instructions while tracking what the registers hold.

The emitter knows, at each point of the code it writes, which registers hold
a RAM byte or a constant, so that the patterns reuse a value already in a
register instead of loading it again. Jumps record what is known at their
target; a label keeps only what every way into it agrees on. A label some
later code jumps back to (a loop) knows nothing. A skip instruction (SBRS...)
is a branch over the next instruction.

Register conventions: r2 is always zero; r3..r17 hold bits (memory.py); the
integer patterns compute in A = r18..r21 and B = r22..r25, with r26..r31 and
r0, r1 as scratch. The reduced core (r16..r31 only) has its zero in r16 and
loads bytes to test into r31 (memory.REGISTERS).
"""

from __future__ import annotations

from ..image import LoopBound
from . import asm as a
from . import isa
from .memory import REGISTERS

A = (18, 19, 20, 21)
B = (22, 23, 24, 25)
SCRATCH = 26  # an upper register free between integer operations

# registers an instruction writes, by mnemonic: "d" its first operand,
# "dd" the pair starting there, "mul" r1:r0
_WRITES = {op: "d" for op in ("ldi", "mov", "lds", "in_", "ld_x", "lpm_p", "ld_zp", "pop", "add", "adc", "sub", "sbc",
                              "and_", "or_", "eor", "subi", "sbci", "ori", "andi", "com", "neg", "swap", "inc",
                              "dec", "asr", "lsr", "ror", "bld", "lsl", "rol", "clr")}
_WRITES.update(sbiw="dd", movw="dd", mul="mul")
# pointer registers moved by post-increment addressing
_POINTER = {"st_xp": (26, 27), "lpm_p": (30, 31), "ld_zp": (30, 31)}
_SKIPS = set(isa.SKIP_INVERSE)


def _written(op: str, args: tuple) -> tuple[int, ...]:
    kind = _WRITES.get(op)
    regs: tuple[int, ...] = ()
    if kind == "d":
        regs = (args[0],)
    elif kind == "dd":
        regs = (args[0], args[0] + 1)
    elif kind == "mul":
        regs = (0, 1)
    return regs + _POINTER.get(op, ())


class Emitter:
    def __init__(self, assembler: a.Assembler):
        self.asm = assembler
        self.core = assembler.core
        plan = REGISTERS[self.core.name]
        self.zero, self.loaded = plan.zero, plan.loaded
        self._preserved = frozenset((plan.zero, *plan.homes, *plan.temps))
        self.known: dict | None = {}  # register -> ("mem", address) | ("const", byte); None: unreachable
        self._incoming: dict[str, list[dict]] = {}
        self._skip_state: dict | None = None  # what was known before a skip instruction
        self._labels = 0
        self._loops: set[str] = set()  # labels placed as loop heads
        self._placed: set[str] = set()
        self.bounds: dict[str, LoopBound] = {}  # loop heads and their bounds, for the scan-time budget

    # --- labels and control flow -------------------------------------------------

    def new_label(self, hint: str = ".L") -> str:
        self._labels += 1
        return f"{hint}{self._labels}"

    def _record(self, target: str) -> None:
        # what a backward jump knows reaches a label already written: only a
        # loop head, which assumes nothing, may be jumped back to
        assert target not in self._placed or target in self._loops, f"backward jump to {target}"
        if self.known is not None:
            self._incoming.setdefault(target, []).append(dict(self.known))

    def _after(self, pending: dict | None) -> None:
        """After an instruction that a skip instruction just before it may
        have skipped: keep only what both ways know."""
        if pending is None:
            return
        if self.known is None:
            self.known = pending
        else:
            self.known = {r: v for r, v in self.known.items() if pending.get(r) == v}

    def label(self, name: str, loop: bool = False, comment: str = "", bound: LoopBound | None = None) -> None:
        """A label; `loop`: later code may jump back to it (or call it), so
        nothing is known there; a loop head gives its `bound`."""
        if bound is not None:
            self.bounds[name] = bound
        self._placed.add(name)
        if loop:
            self._loops.add(name)
        states = self._incoming.pop(name, []) + ([self.known] if self.known is not None else [])
        if loop or not states:
            self.known = {}
        else:
            first, *rest = states
            self.known = {r: v for r, v in first.items() if all(s.get(r) == v for s in rest)}
        self.asm.label(name, comment)

    def jump(self, target: str) -> None:
        pending, self._skip_state = self._skip_state, None
        self._record(target)
        self.asm.jump(target)
        self.known = None
        self._after(pending)

    def branch(self, op: str, target: str) -> None:
        pending, self._skip_state = self._skip_state, None
        self._record(target)
        self.asm.branch(op, target)
        self._after(pending)

    def call(self, target: str) -> None:
        """A call to a routine, which may change any scratch register."""
        pending, self._skip_state = self._skip_state, None
        self.asm.call(target)
        self.forget_scratch()
        self._after(pending)

    def end_path(self) -> None:
        """After RET or an endless loop: nothing falls through."""
        self.known = None

    def comment(self, text: str) -> None:
        self.asm.comment(text)

    # --- instructions ------------------------------------------------------------------

    def ins(self, op: str, *args: int, comment: str = "") -> None:
        """Write an instruction and forget what the registers it writes held."""
        pending, self._skip_state = self._skip_state, None
        self.asm.emit(op, *args, comment=comment)
        if self.known is not None:
            for reg in _written(op, args):
                self.known.pop(reg, None)
        self._after(pending)
        if op in _SKIPS and self.known is not None:
            self._skip_state = dict(self.known)

    def load_address(self, low: int, high: int, label: str) -> None:
        """low:high = a label's byte address in flash (for LPM), or on the
        reduced core its data address (for LD)."""
        for reg, upper in ((low, False), (high, True)):
            self._skip_state = None
            self.asm.address(reg, label, upper, self.core.flash_data or 0)
            if self.known is not None:
                self.known.pop(reg, None)

    def pair(self, dst: int, src: int) -> None:
        """dst:dst+1 = src:src+1, by MOVW where the core has it."""
        if self.core.has("movw"):
            self.ins("movw", dst, src)
        else:
            self.ins("mov", dst, src)
            self.ins("mov", dst + 1, src + 1)

    def bit_io(self, address: int) -> int | None:
        """The I/O address SBI/CBI/SBIS/SBIC reach a data address by, or None."""
        if self.core.io_offset <= address < self.core.bit_io_end:
            return address - self.core.io_offset
        return None

    def holds(self, reg: int, what: tuple) -> None:
        """Note that `reg` now holds `what`; only after an instruction no
        skip instruction guards."""
        if self.known is not None and self._skip_state is None:
            self.known[reg] = what

    def forget_address(self, address: int) -> None:
        """A store to RAM: registers holding its old value are stale."""
        if self.known is not None:
            for reg, value in list(self.known.items()):
                if value == ("mem", address):
                    del self.known[reg]

    def forget_memory(self) -> None:
        """A store to an address not known when compiling: no RAM byte a
        register holds can be trusted."""
        if self.known is not None:
            self.known = {r: v for r, v in self.known.items() if v[0] != "mem"}

    def forget_scratch(self) -> None:
        if self.known is not None:
            self.known = {r: v for r, v in self.known.items() if r in self._preserved}

    def holder(self, what: tuple) -> int | None:
        if self.known is None:
            return None
        for reg, value in self.known.items():
            if value == what:
                return reg
        return None

    # --- bytes ------------------------------------------------------------------------------

    def load_byte(self, address: int, reg: int, ram: bool) -> None:
        """reg = the data-space byte (RAM, or an I/O register read afresh)."""
        if ram:
            held = self.holder(("mem", address))
            if held == reg:
                return
            if held is not None:
                self.ins("mov", reg, held)
                self.holds(reg, ("mem", address))
                return
        if address < self.core.io_end:
            self.ins("in_", reg, address - self.core.io_offset)
        else:
            self.ins("lds", reg, address)
        if ram:
            self.holds(reg, ("mem", address))

    def store_byte(self, address: int, reg: int, ram: bool) -> None:
        if address < self.core.io_end:
            self.ins("out", address - self.core.io_offset, reg)
        else:
            self.ins("sts", address, reg)
        if ram:
            self.forget_address(address)
            if reg != self.zero:
                self.holds(reg, ("mem", address))

    def constant(self, value: int, reg: int) -> None:
        """reg = a byte constant (reg must be r16..r31)."""
        value &= 0xFF
        held = self.holder(("const", value))
        if held == reg:
            return
        if held is not None:
            self.ins("mov", reg, held)
        else:
            self.ins("ldi", reg, value)
        self.holds(reg, ("const", value))

    def constant_reg(self, value: int, spare: int = SCRATCH) -> int:
        """A register holding a byte constant: the zero register for zero, one
        that already holds it, or `spare` loaded with it."""
        value &= 0xFF
        if value == 0:
            return self.zero
        held = self.holder(("const", value))
        if held is not None:
            return held
        self.constant(value, spare)
        return spare
