"""Subroutines written once when used, on the scratch bytes A, B, C (4 each),
the counter D and the spare E; each is labelled by its name and its width.

| routine    | does                                                               |
|------------|--------------------------------------------------------------------|
| mulN       | C = A * B modulo 2^(8N): add A for each 1 bit shifted out of B      |
| udivmodN   | A = A / B, C = A % B, unsigned, restoring (8N steps)               |
| divmodN    | the signed version: C division, the remainder has A's sign         |
| bin2bcd    | A0:A1 (0..9999) to unpacked BCD digits A0 (ones) .. A3 (thousands) |
| bcd2bin    | the inverse                                                        |

Every loop is bounded: mulN runs at most 8N times, udivmodN exactly 8N.
"""

from __future__ import annotations

from collections.abc import Callable

from ..image import LoopBound
from . import integers as ints
from .emit import C, Emitter, F, W, Z
from .integers import Byte, Scratch


def negate(e: Emitter, regs: list[int]) -> None:
    for reg in regs:
        e.ins("comf", reg, F)
    ints.add_constant(e, regs, 1)


def _shift_left(e: Emitter, regs: list[int], clear: bool = True) -> None:
    if clear:
        ints.shift_once(e, "shl", regs)
        return
    for reg in regs:
        e.ins("rlf", reg, F)


def _shift_right(e: Emitter, regs: list[int]) -> None:
    ints.shift_once(e, "sr0", regs)


def mul(e: Emitter, s: Scratch, n: int) -> None:
    A, B, R = s.A[:n], s.B[:n], s.C[:n]
    for reg in R:
        e.ins("clrf", reg)
    top, skip = e.new_label("mul"), e.new_label("mul")
    e.label(top, loop=True, bound=LoopBound(8 * n + 1, f"a {8 * n}-bit multiplication, one bit a pass"))
    e.ins("movf", B[0], W)
    for reg in B[1:]:
        e.ins("iorwf", reg, W)
    e.ins("btfsc", e.status, Z)
    e.ins("return")
    e.forget_w()
    _shift_right(e, B)
    e.ins("btfss", e.status, C)
    e.goto(skip)
    ints.add_files(e, R, A)
    e.label(skip)
    _shift_left(e, A)
    e.goto(top)


def udivmod(e: Emitter, s: Scratch, n: int) -> None:
    A, B, R = s.A[:n], s.B[:n], s.C[:n]
    for reg in R:
        e.ins("clrf", reg)
    e.ins("movlw", 8 * n)
    e.ins("movwf", s.D)
    top, next_ = e.new_label("div"), e.new_label("div")
    e.label(top, loop=True, bound=LoopBound(8 * n, f"a {8 * n}-bit division, one bit a pass"))
    _shift_left(e, A)
    _shift_left(e, R, clear=False)
    ints.compare_files(e, R, B)  # C = R >= B
    e.ins("btfss", e.status, C)
    e.goto(next_)
    ints.sub_files(e, R, B)
    e.ins("bsf", A[0], 0)
    e.label(next_)
    e.ins("decfsz", s.D, F)
    e.goto(top)
    e.ins("return")


def divmod_(e: Emitter, s: Scratch, n: int) -> None:
    A, B, R = s.A[:n], s.B[:n], s.C[:n]
    e.ins("clrf", s.E)
    for regs, flags in ((A, 0b11), (B, 0b10)):
        positive = e.new_label("div")
        e.ins("btfss", regs[-1], 7)
        e.goto(positive)
        negate(e, regs)
        e.ins("movlw", flags)
        e.ins("xorwf", s.E, F)
        e.label(positive)
    e.call(f"udivmod{n}")
    for regs, bit in ((A, 1), (R, 0)):
        done = e.new_label("div")
        e.ins("btfss", s.E, bit)
        e.goto(done)
        negate(e, regs)
        e.label(done)
    e.ins("return")


def bin2bcd(e: Emitter, s: Scratch) -> None:
    """Counting subtractions of 1000, 100 and 10 from the value in C0:C1."""
    A, R = s.A, s.C[:2]
    e.ins("movf", A[0], W)
    e.ins("movwf", R[0])
    e.ins("movf", A[1], W)
    e.ins("movwf", R[1])
    for digit, step in ((A[3], 1000), (A[2], 100), (A[1], 10)):
        e.ins("clrf", digit)
        top, done = e.new_label("bcd"), e.new_label("bcd")
        # a 16-bit value holds 65 thousands at most; then fewer than ten of each
        e.label(top, loop=True, bound=LoopBound(66 if step == 1000 else 10, f"BIN2BCD, counting {step}s"))
        ints.compare_files(e, R, [Byte("const", step & 0xFF), Byte("const", step >> 8)])
        e.ins("btfss", e.status, C)
        e.goto(done)
        ints.add_constant(e, R, -step)
        e.ins("incf", digit, F)
        e.goto(top)
        e.label(done)
    e.ins("movf", R[0], W)
    e.ins("movwf", A[0])
    e.ins("return")


def bcd2bin(e: Emitter, s: Scratch) -> None:
    """((A3 * 10 + A2) * 10 + A1) * 10 + A0 on the low nibbles, in C0:C1."""
    A, R = s.A, s.C[:2]
    e.ins("clrf", R[1])
    e.ins("movf", A[3], W)
    e.ins("andlw", 0x0F)
    e.ins("movwf", R[0])
    for digit in (A[2], A[1], A[0]):
        # R = R * 10 = R * 8 + R * 2, through B0:B1
        _shift_left(e, R)
        e.ins("movf", R[0], W)
        e.ins("movwf", s.B[0])
        e.ins("movf", R[1], W)
        e.ins("movwf", s.B[1])
        _shift_left(e, R)
        _shift_left(e, R)
        ints.add_files(e, R, s.B[:2])
        e.ins("movf", digit, W)
        e.ins("andlw", 0x0F)
        e.ins("addwf", R[0], F)
        e.ins("btfsc", e.status, C)
        e.ins("incf", R[1], F)
    for i in range(2):
        e.ins("movf", R[i], W)
        e.ins("movwf", A[i])
    e.ins("clrf", A[2])
    e.ins("clrf", A[3])
    e.ins("return")


Multiply = Callable[[Emitter, Scratch, int], None]


def _writer(name: str, multiply: Multiply):
    if name in ("bin2bcd", "bcd2bin"):
        return (bin2bcd if name == "bin2bcd" else bcd2bin), None, ()
    for prefix, fn in (("udivmod", udivmod), ("divmod", divmod_), ("mul", multiply)):
        if name.startswith(prefix):
            n = int(name[len(prefix):])
            return fn, n, (f"udivmod{n}",) if prefix == "divmod" else ()
    raise KeyError(name)


def write_routines(e: Emitter, scratch: tuple[int, ...], wanted: set[str], multiply: Multiply = mul) -> None:
    """Each routine asked for (and those it calls), labelled by its name;
    `multiply` writes mulN (the PIC18 has a hardware multiplier)."""
    s = Scratch(scratch)
    todo = set(wanted)
    for name in list(todo):
        todo.update(_writer(name, multiply)[2])
    for name in sorted(todo):
        fn, n, _ = _writer(name, multiply)
        e.label(name, loop=True)
        if n is None:
            fn(e, s)
        else:
            fn(e, s, n)
        e.end_path()
