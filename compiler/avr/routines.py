"""Subroutines the patterns call, written once after the scan when used.

Each takes its operands in A = r18..r21 and B = r22..r25 and returns its
result in A (the remainder of a division in r26..r29); it may change any
register but r2..r17.
"""

from __future__ import annotations

from ..image import LoopBound
from .emit import A, B, Emitter

R = (26, 27, 28, 29)
COUNTER = 30
SIGNS = 31


def _negate(e: Emitter, regs) -> None:
    for reg in reversed(regs[1:]):
        e.ins("com", reg)
    e.ins("neg", regs[0])
    for reg in regs[1:]:
        e.ins("sbci", reg, 0xFF)


def mul32(e: Emitter) -> None:
    """A = A * B, the low 32 bits (the same for signed and unsigned)."""
    a, b = A, B
    e.ins("mul", a[0], b[0])
    e.ins("movw", R[0], 0)
    e.ins("mul", a[0], b[2])
    e.ins("movw", R[2], 0)
    for i, j in ((1, 1), (2, 0)):
        e.ins("mul", a[i], b[j])
        e.ins("add", R[2], 0)
        e.ins("adc", R[3], 1)
    for i, j in ((0, 3), (3, 0), (1, 2), (2, 1)):
        e.ins("mul", a[i], b[j])
        e.ins("add", R[3], 0)
    for i, j in ((0, 1), (1, 0)):
        e.ins("mul", a[i], b[j])
        e.ins("add", R[1], 0)
        e.ins("adc", R[2], 1)
        e.ins("adc", R[3], e.zero)
    e.ins("movw", a[0], R[0])
    e.ins("movw", a[2], R[2])
    e.ins("ret")


def _udivmod(e: Emitter, width: int, name: str) -> None:
    """Unsigned A / B: quotient in A, remainder in R (restoring division; a
    zero divisor gives an all-ones quotient)."""
    a, b, r = A[:width], B[:width], R[:width]
    for reg in r:
        e.ins("clr", reg)
    e.ins("ldi", COUNTER, 8 * width)
    top, smaller = e.new_label(f"{name}_bit"), e.new_label(f"{name}_next")
    e.label(top, loop=True, bound=LoopBound(8 * width, f"a {8 * width}-bit division, one bit a pass"))
    e.ins("lsl", a[0])
    for reg in a[1:] + r:
        e.ins("rol", reg)
    for i, (x, y) in enumerate(zip(r, b)):
        e.ins("cp" if i == 0 else "cpc", x, y)
    e.branch("brcs", smaller)
    for i, (x, y) in enumerate(zip(r, b)):
        e.ins("sub" if i == 0 else "sbc", x, y)
    e.ins("inc", a[0])
    e.label(smaller)
    e.ins("dec", COUNTER)
    e.branch("brne", top)
    e.ins("ret")


def udivmod16(e: Emitter) -> None:
    _udivmod(e, 2, "udivmod16")


def udivmod32(e: Emitter) -> None:
    _udivmod(e, 4, "udivmod32")


def _divmod(e: Emitter, width: int, unsigned: str) -> None:
    """Signed A / B as C does it: the quotient truncated toward zero, the
    remainder with the dividend's sign."""
    a, b, r = A[:width], B[:width], R[:width]
    e.ins("mov", SIGNS, a[-1])
    e.ins("eor", SIGNS, b[-1])  # bit 7: the quotient's sign
    e.ins("bst", a[-1], 7)  # T: the remainder's sign
    for regs in (a, b):
        skip = e.new_label()
        e.ins("sbrs", regs[-1], 7)
        e.jump(skip)
        _negate(e, regs)
        e.label(skip)
    e.call(unsigned)
    skip = e.new_label()
    e.ins("sbrs", SIGNS, 7)
    e.jump(skip)
    _negate(e, a)
    e.label(skip)
    skip = e.new_label()
    e.branch("brtc", skip)
    _negate(e, r)
    e.label(skip)
    e.ins("ret")


def divmod16(e: Emitter) -> None:
    _divmod(e, 2, "udivmod16")


def divmod32(e: Emitter) -> None:
    _divmod(e, 4, "udivmod32")


def bin2bcd(e: Emitter) -> None:
    """A0:A1 (0..9999) to unpacked BCD: A0 ones, A1 tens, A2 hundreds, A3
    thousands, by counting subtractions."""
    e.pair(R[0], A[0])
    for digit, step in ((A[3], 1000), (A[2], 100)):
        e.ins("clr", digit)
        top, done = e.new_label("bcd"), e.new_label("bcd")
        # a 16-bit value holds 65 thousands at most; then fewer than ten of each
        e.label(top, loop=True, bound=LoopBound(66 if step == 1000 else 10, f"BIN2BCD, counting {step}s"))
        e.ins("subi", R[0], step & 0xFF)
        e.ins("sbci", R[1], step >> 8)
        e.branch("brcs", done)
        e.ins("inc", digit)
        e.jump(top)
        e.label(done)
        e.ins("subi", R[0], -step & 0xFF)
        e.ins("sbci", R[1], (-step >> 8) & 0xFF)
    e.ins("clr", A[1])
    top, done = e.new_label("bcd"), e.new_label("bcd")
    e.label(top, loop=True, bound=LoopBound(10, "BIN2BCD, counting 10s"))
    e.ins("subi", R[0], 10)
    e.branch("brcs", done)
    e.ins("inc", A[1])
    e.jump(top)
    e.label(done)
    e.ins("subi", R[0], -10 & 0xFF)
    e.ins("mov", A[0], R[0])
    e.ins("ret")


def bcd2bin(e: Emitter) -> None:
    """The low nibbles of A0..A3 as decimal digits (A0 the ones) to A0:A1."""
    for reg in A:
        e.ins("andi", reg, 0x0F)
    e.ins("ldi", R[0], 10)
    e.ins("mul", A[3], R[0])
    e.ins("add", 0, A[2])  # thousands * 10 + hundreds
    e.ins("mul", 0, R[0])
    e.ins("add", 0, A[1])
    e.ins("adc", 1, e.zero)
    e.ins("movw", R[2], 0)  # (.. * 10 + tens), times 10 below
    e.ins("lsl", R[2])
    e.ins("rol", R[3])
    e.ins("movw", COUNTER, R[2])
    e.ins("lsl", R[2])
    e.ins("rol", R[3])
    e.ins("lsl", R[2])
    e.ins("rol", R[3])
    e.ins("add", R[2], COUNTER)
    e.ins("adc", R[3], SIGNS)
    e.ins("add", R[2], A[0])
    e.ins("adc", R[3], e.zero)
    e.ins("movw", A[0], R[2])
    e.ins("ret")


def mul32_shift(e: Emitter) -> None:
    """mul32 on a core without MUL (the ATtiny85): B's bits from the lowest,
    A added for each one set, A doubled each pass."""
    for reg in R:
        e.ins("clr", reg)
    e.ins("ldi", COUNTER, 32)
    top, clear = e.new_label("mul_bit"), e.new_label("mul_next")
    e.label(top, loop=True, bound=LoopBound(32, "a 32-bit multiplication, one bit a pass"))
    e.ins("lsr", B[3])
    for reg in reversed(B[:3]):
        e.ins("ror", reg)
    e.branch("brcc", clear)
    e.ins("add", R[0], A[0])
    for i in range(1, 4):
        e.ins("adc", R[i], A[i])
    e.label(clear)
    e.ins("lsl", A[0])
    for reg in A[1:]:
        e.ins("rol", reg)
    e.ins("dec", COUNTER)
    e.branch("brne", top)
    e.pair(A[0], R[0])
    e.pair(A[2], R[2])
    e.ins("ret")


def bcd2bin_shift(e: Emitter) -> None:
    """bcd2bin on a core without MUL: each step times ten as (x * 4 + x) * 2."""
    for reg in A:
        e.ins("andi", reg, 0x0F)
    e.ins("mov", R[0], A[3])
    e.ins("clr", R[1])
    for digit in (A[2], A[1], A[0]):
        e.pair(R[2], R[0])
        for _ in range(2):
            e.ins("lsl", R[0])
            e.ins("rol", R[1])
        e.ins("add", R[0], R[2])
        e.ins("adc", R[1], R[3])
        e.ins("lsl", R[0])
        e.ins("rol", R[1])
        e.ins("add", R[0], digit)
        e.ins("adc", R[1], e.zero)
    e.pair(A[0], R[0])
    e.ins("ret")


ROUTINES = {"mul32": (mul32, ()), "udivmod16": (udivmod16, ()), "udivmod32": (udivmod32, ()),
            "divmod16": (divmod16, ("udivmod16",)), "divmod32": (divmod32, ("udivmod32",)),
            "bin2bcd": (bin2bcd, ()), "bcd2bin": (bcd2bin, ()),
            "mul32_shift": (mul32_shift, ()), "bcd2bin_shift": (bcd2bin_shift, ())}
# what a core without MUL calls instead
WITHOUT_MUL = {"mul32": "mul32_shift", "bcd2bin": "bcd2bin_shift"}


def write_routines(e: Emitter, wanted: set[str]) -> None:
    """Each routine asked for (and those it calls), labelled by its name."""
    todo = set(wanted)
    for name in list(todo):
        todo.update(ROUTINES[name][1])
    for name in sorted(todo):
        e.label(name, loop=True)
        ROUTINES[name][0](e)
        e.end_path()
