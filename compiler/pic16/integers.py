"""Integer patterns for the PIC16: 8-bit operations through W, byte by byte
from the least significant, with the carry between bytes.

An operand byte is a constant, a file register, or the sign extension of a
narrower variable (computed into W, or into a scratch byte where an
instruction needs a file register). Results are computed in place in the
destination when it is a RAM variable of the operation's width in a bank the
other operand shares, else in the scratch bytes A, B, C (common RAM when the
part has it) and stored from there.

| operation            | pattern                                                         |
|----------------------|-----------------------------------------------------------------|
| x + 1                | INCF, then INCF of each higher byte while the lower one is zero  |
| x + k                | MOVLW/ADDWF, carry in by choosing k_i or k_i + 1                |
| x + y, x - y         | MOVF y_i; BTFSC C; INCFSZ y_i,W; ADDWF/SUBWF x_i                 |
|                      | (the enhanced core: MOVF y_i or MOVLW k_i; ADDWFC/SUBWFB x_i)    |
| x & y, x | y, x ^ y  | ANDWF/IORWF/XORWF byte by byte, constants' identity bytes skipped|
| x <rel> y            | signs flipped (XOR 0x80), an unsigned subtraction chain, C       |
| x * y, x / y, shifts | the routines (routines.py) on A, B and C                        |
"""

from __future__ import annotations

from dataclasses import dataclass

from lang.semantics import ir

from .. import analysis
from ..analysis import value_size
from ..image import LoopBound
from . import bits
from .emit import C, Emitter, F, W, Z
from .memory import FileBit


@dataclass(frozen=True)
class Byte:
    """One byte of an operand at some width."""

    kind: str  # "const", "mem" or "ext" (the sign of the byte at `value`)
    value: int  # the constant, or the file address


def storage(cx, operand):
    var = operand.var if isinstance(operand, ir.Byte) else operand
    return cx.layout.vars[var.name]


def size(cx, operand) -> int:
    """Bytes that hold the operand's value as a signed number."""
    return value_size(operand, lambda var: storage(cx, var).size)


def target_size(cx, target) -> int:
    return analysis.target_size(target, lambda var: storage(cx, var).size)


def byte(cx, operand, i: int) -> Byte:
    """Byte i of the operand, read as a signed number (an ir.Byte unsigned)."""
    if isinstance(operand, ir.Const):
        return Byte("const", (operand.value >> 8 * i) & 0xFF)
    st = storage(cx, operand)
    if isinstance(operand, ir.Byte):
        if i:
            return Byte("const", 0)
        if operand.index < st.size:
            return Byte("mem", st.addr + operand.index)
        return Byte("ext", st.addr + st.size - 1)
    if i < st.size:
        return Byte("mem", st.addr + i)
    return Byte("ext", st.addr + st.size - 1)


def target_bytes(cx, target) -> list[int]:
    st = storage(cx, target)
    if isinstance(target, ir.Byte):
        return [st.addr + target.index]
    return [st.addr + i for i in range(st.size)]


def load_w(e: Emitter, b: Byte) -> None:
    """W = the byte."""
    if b.kind == "const":
        e.load_constant(b.value)
    elif b.kind == "mem":
        e.load(b.value)
    elif not e.w_holds(("ext", b.value)):
        e.select(b.value)
        e.ins("movlw", 0)
        e.ins("btfsc", b.value, 7)
        e.ins("movlw", 0xFF)
        e.note_w(("ext", b.value))


def put(e: Emitter, b: Byte, address: int) -> None:
    """The file register = the byte."""
    if b.kind == "mem" and b.value == address:
        return
    if b.kind == "const" and b.value == 0:
        e.ins("clrf", address)
        return
    if b.kind == "mem":
        e.copy(b.value, address)
        return
    load_w(e, b)
    e.store(address)


def as_file(cx, b: Byte, spare: int) -> Byte:
    """The byte in a file register: a sign extension is computed into `spare`."""
    if b.kind != "ext":
        return b
    put(cx.e, b, spare)
    return Byte("mem", spare)


def copy_in(cx, operand, regs) -> None:
    for i, reg in enumerate(regs):
        put(cx.e, byte(cx, operand, i), reg)


def copy_out(cx, regs, target) -> None:
    for reg, address in zip(regs, target_bytes(cx, target)):
        put(cx.e, Byte("mem", reg), address)


class Scratch:
    """The scratch bytes by name: A, B and C (4 each) the operands and results of the routines
    (routines.py), the counter D and the spare E."""

    def __init__(self, addresses: tuple[int, ...]):
        self.A, self.B, self.C = list(addresses[0:4]), list(addresses[4:8]), list(addresses[8:12])
        self.D, self.E = addresses[12], addresses[13]


def scratch(cx, which: str, n: int) -> list[int]:
    return getattr(Scratch(cx.layout.scratch), which)[:n]


def move(cx, op: ir.Move) -> None:
    n = target_size(cx, op.dst)
    source = [byte(cx, op.src, i) for i in range(n)]
    for b, address in zip(source, target_bytes(cx, op.dst)):
        put(cx.e, b, address)


# --- add, sub, logic -----------------------------------------------------------------------

def _same_bank(e: Emitter, *addresses: int) -> bool:
    banks = {e.core.wanted(a) for a in addresses if not e.reaches(a)}
    return len(banks) <= 1


def _in_place(cx, op, n: int) -> list[int] | None:
    """The destination's bytes when the operation can run on them."""
    if isinstance(op.dst, ir.Byte) or not storage(cx, op.dst).ram or op.overflow:
        return None
    dst = target_bytes(cx, op.dst)
    others = [byte(cx, op.b, i) for i in range(n)] + [byte(cx, op.a, i) for i in range(n)]
    files = [b.value for b in others if b.kind != "const"]
    if not _same_bank(cx.e, *dst, *files):
        return None
    if op.b != op.a and set(dst) & {b.value for b in others[:n] if b.kind != "const"}:
        return None  # b is (part of) the destination: it would be overwritten before it is read
    return dst


def add_constant(e: Emitter, regs: list[int], k: int) -> None:
    """regs += k (modulo), carries between the bytes."""
    n = len(regs)
    k &= (1 << 8 * n) - 1
    if k == 0:
        return
    if k == 1:
        e.ins("incf", regs[0], F)
        for reg in regs[1:]:
            e.select(reg)
            e.ins("btfsc", e.status, Z)
            e.ins("incf", reg, F)
        return
    first = next(i for i in range(n) if (k >> 8 * i) & 0xFF)
    e.load_constant((k >> 8 * first) & 0xFF)
    e.ins("addwf", regs[first], F)
    for i in range(first + 1, n):
        ki = (k >> 8 * i) & 0xFF
        reg = regs[i]
        if e.core.carry_ops:
            e.load_constant(ki)
            e.ins("addwfc", reg, F)
        elif i == n - 1 and ki == 0:
            e.select(reg)
            e.ins("btfsc", e.status, C)
            e.ins("incf", reg, F)
        elif ki == 0xFF:
            # with a carry in, adding 0x100 leaves the byte and carries out
            e.select(reg)
            e.ins("movlw", 0xFF)
            e.ins("btfss", e.status, C)
            e.ins("addwf", reg, F)
        else:
            e.ins("movlw", ki)
            e.ins("btfsc", e.status, C)
            e.ins("movlw", ki + 1)
            e.ins("addwf", reg, F)


def near(cx, b: list[Byte], regs: list[int]) -> list[Byte]:
    """The bytes as constants or file registers an instruction on `regs`
    reaches in the same bank: if a sign extension or a byte in another bank
    is among them, the operand is copied to the scratch B first."""
    e = cx.e
    if all(bi.kind == "const" or (bi.kind == "mem" and _same_bank(e, bi.value, regs[0])) for bi in b):
        return b
    spare = scratch(cx, "B", len(b))
    out = []
    for bi, reg in zip(b, spare):
        if bi.kind != "const":
            put(e, bi, reg)
            bi = Byte("mem", reg)
        out.append(bi)
    return out


def chain(e: Emitter, kind: str, regs: list[int], b: list[Byte]) -> None:
    """regs = regs + b or regs - b (kind "add", "sub"), or only C = regs >= b
    unsigned (kind "cmp", nothing written), byte by byte with the carry.
    The bytes of b are constants or files in the bank of regs."""
    op = {"add": "addwf", "sub": "subwf", "cmp": "subwf"}[kind]
    dest = W if kind == "cmp" else F
    borrow = kind != "add"  # C clear means a borrow
    for i, (reg, bi) in enumerate(zip(regs, b)):
        if i == 0:
            load_w(e, bi)
            e.ins(op, reg, dest)
        elif e.core.carry_ops:
            load_w(e, bi)
            e.select(reg)
            e.ins("addwfc" if kind == "add" else "subwfb", reg, dest)
        elif bi.kind == "const" and bi.value == 0xFF:
            # with a carry in, adding (a borrow: subtracting) 0x100 leaves
            # the byte and carries (borrows) out
            e.select(reg)
            e.ins("movlw", 0xFF)
            e.ins("btfsc" if borrow else "btfss", e.status, C)
            e.ins(op, reg, dest)
        elif bi.kind == "const":
            e.ins("movlw", bi.value)
            e.ins("btfss" if borrow else "btfsc", e.status, C)
            e.ins("movlw", bi.value + 1)
            e.ins(op, reg, dest)
        else:
            e.select(reg)
            e.ins("movf", bi.value, W)
            e.ins("btfss" if borrow else "btfsc", e.status, C)
            e.ins("incfsz", bi.value, W)
            e.ins(op, reg, dest)
    if kind == "cmp":
        e.forget_w()


def add_files(e: Emitter, regs: list[int], b: list[int]) -> None:
    chain(e, "add", regs, [Byte("mem", x) for x in b])


def sub_files(e: Emitter, regs: list[int], b: list[int]) -> None:
    chain(e, "sub", regs, [Byte("mem", x) for x in b])


def compare_files(e: Emitter, regs: list[int], b: list) -> None:
    """C = regs >= b, unsigned; b: file addresses or Bytes."""
    chain(e, "cmp", regs, [x if isinstance(x, Byte) else Byte("mem", x) for x in b])


_LOGIC = {"and": "andwf", "or": "iorwf", "xor": "xorwf"}


def _logic(e: Emitter, kind: str, regs: list[int], b: list[Byte]) -> None:
    for reg, bi in zip(regs, b):
        if bi.kind == "const":
            if (kind, bi.value) in (("and", 0xFF), ("or", 0), ("xor", 0)):
                continue
            if (kind, bi.value) == ("and", 0):
                e.ins("clrf", reg)
                continue
            if kind == "xor" and bi.value == 0xFF:
                e.ins("comf", reg, F)
                continue
        load_w(e, bi)
        e.ins(_LOGIC[kind], reg, F)


def arith(cx, op: ir.Arith) -> None:
    if op.op == "mul":
        multiply(cx, op)
        return
    e = cx.e
    n = target_size(cx, op.dst)
    width = max(n, size(cx, op.a), size(cx, op.b)) if op.overflow else n
    a, b = op.a, op.b
    if op.op in ("add", "and", "or", "xor") and not isinstance(op.dst, ir.Byte) and b == op.dst and a != op.dst:
        a, b = b, a  # commutative: work on the destination's own value
    place = _in_place(cx, ir.Arith(op.op, op.dst, a, b, op.overflow), width)
    regs = place if place is not None else scratch(cx, "A", width)
    if op.overflow:
        # the signs before the operation, for the overflow test: C0 = a's, C1 = a's xor b's
        load_w(e, byte(cx, a, width - 1))
        e.store(cx.layout.scratch[8])
        load_w(e, byte(cx, b, width - 1))
        e.ins("xorwf", cx.layout.scratch[8], W)
        e.store(cx.layout.scratch[9])
    if not (place is not None and a == op.dst):
        copy_in(cx, a, regs)
    b_bytes = [byte(cx, b, i) for i in range(width)]
    if op.op in _LOGIC:
        _logic(e, op.op, regs, b_bytes)
    elif isinstance(b, ir.Const) and not op.overflow:
        add_constant(e, regs, b.value if op.op == "add" else -b.value)
    else:
        chain(e, op.op, regs, near(cx, b_bytes, regs))
    if op.overflow:
        _overflow(cx, op.op, regs, n, op.overflow)
    if place is None:
        copy_out(cx, regs, op.dst)


def multiply(cx, op: ir.Arith) -> None:
    n = target_size(cx, op.dst)
    s = Scratch(cx.layout.scratch)
    copy_in(cx, op.a, s.A[:n])
    copy_in(cx, op.b, s.B[:n])
    cx.e.call(cx.routine(f"mul{n}"))
    copy_out(cx, s.C[:n], op.dst)


def divide(cx, op: ir.Divide) -> None:
    n = target_size(cx, op.dst)
    widest = max(n, size(cx, op.a), size(cx, op.b), target_size(cx, op.remainder) if op.remainder else 1)
    width = min(widest, 4)
    s = Scratch(cx.layout.scratch)
    copy_in(cx, op.a, s.A[:width])
    copy_in(cx, op.b, s.B[:width])
    cx.e.call(cx.routine(f"divmod{width}"))
    if op.remainder is not None:
        copy_out(cx, s.C, op.remainder)
    copy_out(cx, s.A if op.op == "div" else s.C, op.dst)


def _overflow(cx, kind: str, regs: list[int], n: int, flag: ir.Bit) -> None:
    """Set the flag when the result does not fit n bytes: a signed overflow at
    the width computed, or bytes above n that are not the sign extension."""
    e = cx.e
    sign_a, signs_differ = cx.layout.scratch[8], cx.layout.scratch[9]
    overflow, done = e.new_label(), e.new_label()
    # signed overflow: the result's sign differs from a's, and (add) the
    # operands' signs agree or (sub) differ
    e.load(regs[-1])
    e.ins("xorwf", sign_a, W)
    e.store(sign_a)
    bits.when(e, FileBit(signs_differ, 7), kind == "add", lambda: e.ins("clrf", sign_a))
    bits.jump_if(e, FileBit(sign_a, 7), True, overflow)
    for reg in regs[n:]:
        load_w(e, Byte("ext", regs[n - 1]))
        e.ins("xorwf", reg, W)
        e.ins("btfss", e.status, Z)
        e.goto(overflow)
    e.goto(done)
    e.label(overflow)
    bits.write(e, cx.bit(flag), True)
    e.label(done)


def unary(cx, op: ir.Unary) -> None:
    e = cx.e
    n = target_size(cx, op.dst)
    place = None if isinstance(op.dst, ir.Byte) or not storage(cx, op.dst).ram else target_bytes(cx, op.dst)
    if place is not None and not _same_bank(e, *place):
        place = None
    regs = place if place is not None else scratch(cx, "A", n)
    copy_in(cx, op.a, regs)
    for reg in regs:
        e.ins("comf", reg, F)
    if op.op == "neg":
        add_constant(e, regs, 1)
    if place is None:
        copy_out(cx, regs, op.dst)


# --- comparisons -------------------------------------------------------------------------

_SWAPPED = {"==": "==", "!=": "!=", "<": ">", ">": "<", "<=": ">=", ">=": "<="}


def compare_jump(cx, op: ir.JumpIf) -> None:
    e = cx.e
    a, rel, b = op.a, op.rel, op.b
    if isinstance(a, ir.Const):
        a, b, rel = b, a, _SWAPPED[rel]
    width = max(size(cx, a), size(cx, b))
    if rel in ("==", "!="):
        _equality(cx, a, b, width, rel == "==", op.target)
        return
    if rel in (">", "<="):
        if isinstance(b, ir.Const):
            # x > k is x >= k+1, x <= k is x < k+1
            b, rel = ir.Const(b.value + 1), ">=" if rel == ">" else "<"
            width = max(width, size(cx, b))
        else:
            a, b, rel = b, a, _SWAPPED[rel]
    if isinstance(b, ir.Const):
        _at_least_constant(cx, a, b.value, width)
    else:
        _at_least(cx, a, b, width)
    bits.jump_if(e, FileBit(e.status, C), rel == ">=", op.target)


def _at_least(cx, a, b, width: int) -> None:
    """C = a >= b (signed): with the sign bits flipped (XOR 0x80) the order is
    the unsigned one, the carry of a - b."""
    e = cx.e
    regs = scratch(cx, "A", width)
    copy_in(cx, a, regs)
    e.ins("movlw", 0x80)
    e.ins("xorwf", regs[-1], F)
    b_bytes = [byte(cx, b, i) for i in range(width)]
    flipped = scratch(cx, "B", width)[-1]
    put(e, b_bytes[-1], flipped)
    e.ins("movlw", 0x80)
    e.ins("xorwf", flipped, F)
    b_bytes[-1] = Byte("mem", flipped)
    chain(e, "cmp", regs, near(cx, b_bytes, regs))


def _at_least_constant(cx, a, k: int, width: int) -> None:
    """C = a >= k (signed), byte by byte from the most significant (its sign
    flipped) while the bytes are equal: ADDLW -k_i leaves C = byte >= k_i and
    Z = byte == k_i."""
    e = cx.e
    done = e.new_label("cmp")
    for i in reversed(range(width)):
        ki = (k >> 8 * i) & 0xFF ^ (0x80 if i == width - 1 else 0)
        load_w(e, byte(cx, a, i))
        if i == width - 1:
            e.ins("xorlw", 0x80)
        if ki:
            e.ins("addlw", 0x100 - ki)
        elif i:
            if i != width - 1:
                e.ins("iorlw", 0)  # Z: the byte is 0
            e.ins("bsf", e.status, C)
        else:
            e.ins("bsf", e.status, C)  # the last byte is at least 0
        if i:
            e.ins("btfss", e.status, Z)
            e.goto(done)
    e.label(done)
    e.forget_w()


def _equality(cx, a, b, width: int, equal: bool, target: str) -> None:
    """Byte by byte: Z after W = a_i XOR b_i (or MOVF a_i,F against 0); the
    last byte jumps on its own result."""
    e = cx.e
    differ = e.new_label("ne") if equal else target
    pairs = []
    for i in range(width):
        ai, bi = byte(cx, a, i), byte(cx, b, i)
        if ai.kind == "const":
            ai, bi = bi, ai
        if ai.kind == "const":
            if ai.value != bi.value:
                e.goto(differ)
                if equal:
                    e.label(differ)
                return
            continue
        pairs.append((ai, bi))
    if not pairs:
        if equal:
            e.goto(target)
        return
    for n, (ai, bi) in enumerate(pairs):
        if bi.kind == "const" and bi.value == 0 and ai.kind == "mem":
            e.ins("movf", ai.value, F)
        elif bi.kind == "const":
            load_w(e, ai)
            e.ins("xorlw", bi.value)
        else:
            bi = as_file(cx, bi, cx.layout.scratch[11])
            load_w(e, ai)
            e.ins("xorwf", bi.value, W)
        if n == len(pairs) - 1 and equal:
            bits.jump_if(e, FileBit(e.status, Z), True, target)
        else:
            bits.jump_if(e, FileBit(e.status, Z), False, differ)
    if equal:
        e.label(differ)


# --- shifts -------------------------------------------------------------------------------

_FIRST_SHIFT = {"shl": "lslf", "sr0": "lsrf", "shr": "asrf"}


def shift_once(e: Emitter, kind: str, regs: list[int]) -> None:
    """One bit: the carry takes what comes in (0, the sign, the bit going round);
    the enhanced core's LSLF, LSRF and ASRF shift the first byte in by themselves."""
    if e.core.carry_ops and kind in _FIRST_SHIFT:
        order = regs if kind == "shl" else list(reversed(regs))
        e.ins(_FIRST_SHIFT[kind], order[0], F)
        for reg in order[1:]:
            e.ins("rlf" if kind == "shl" else "rrf", reg, F)
        return
    if kind in ("shl", "sr0"):
        e.ins("bcf", e.status, C)
    elif kind in ("shr", "rol"):
        e.ins("rlf", regs[-1], W)  # C = the top bit
    else:
        e.ins("rrf", regs[0], W)  # ror: C = the bottom bit
    order = regs if kind in ("shl", "rol") else list(reversed(regs))
    for reg in order:
        e.ins("rlf" if kind in ("shl", "rol") else "rrf", reg, F)


def _repeat(cx, kind: str, regs: list[int]) -> None:
    """Shift D times (D in the scratch counter, 1 to 8 * len(regs))."""
    e = cx.e
    top = e.new_label("shift")
    e.label(top, loop=True, bound=LoopBound(8 * len(regs), f"a shift of {len(regs)} bytes, one bit a pass"))
    shift_once(e, kind, regs)
    e.ins("decfsz", cx.layout.scratch[12], F)
    e.goto(top)


def _count(cx, count, bits_: int, rotate: bool) -> None:
    """D = the number of one-bit shifts a variable count asks for: none when
    it is negative, at most bits_, modulo bits_ for a rotation."""
    e = cx.e
    s = Scratch(cx.layout.scratch)
    negative, have = e.new_label("shift"), e.new_label("shift")
    copy_in(cx, count, s.B)
    e.ins("btfsc", s.B[3], 7)
    e.goto(negative)
    if rotate and bits_ == 24:
        copy_in(cx, count, s.A)
        for reg, value in zip(s.B, (24, 0, 0, 0)):
            put(e, Byte("const", value), reg)
        e.call(cx.routine("udivmod4"))
        e.load(s.C[0])
    elif rotate:
        e.load(s.B[0])
        e.ins("andlw", bits_ - 1)
    else:
        e.load(s.B[1])
        e.ins("iorwf", s.B[2], W)
        e.ins("iorwf", s.B[3], W)
        e.ins("btfss", e.status, Z)
        e.ins("movlw", 0xFF)  # a high byte set: past the width
        e.ins("iorwf", s.B[0], W)
        e.ins("sublw", bits_)
        e.ins("movlw", bits_)
        e.ins("btfss", e.status, C)
        e.goto(have)  # above bits_: bits_ shifts
        e.load(s.B[0])
    e.goto(have)
    e.label(negative)
    e.ins("movlw", 0)
    e.label(have)
    e.store(s.D)


def widen(cx, regs: list[int], w: int, n: int, signed: bool) -> list[int]:
    """regs[:max(w, n)] with the bytes above w the sign (or zero) extension."""
    for reg in regs[w:n]:
        put(cx.e, Byte("ext", regs[w - 1]) if signed else Byte("const", 0), reg)
    return regs[:max(w, n)]


def shift(cx, op: ir.Shift) -> None:
    e = cx.e
    w, n = op.width, target_size(cx, op.dst)
    bits_ = 8 * w
    regs = scratch(cx, "A", 4)
    if isinstance(op.count, ir.Const):
        count = op.count.value % bits_ if op.op in ("rol", "ror") else min(max(op.count.value, 0), bits_)
        copy_in(cx, op.a, regs[:w])
        if count * w <= 8:
            for _ in range(count):
                shift_once(e, op.op, regs[:w])
        elif count:
            put(e, Byte("const", count), cx.layout.scratch[12])
            _repeat(cx, op.op, regs[:w])
    else:
        _count(cx, op.count, bits_, op.op in ("rol", "ror"))
        copy_in(cx, op.a, regs[:w])
        done = e.new_label("shift")
        e.ins("movf", cx.layout.scratch[12], F)
        e.ins("btfsc", e.status, Z)
        e.goto(done)
        _repeat(cx, op.op, regs[:w])
        e.label(done)
    copy_out(cx, widen(cx, regs, w, n, op.op == "shr"), op.dst)


# --- bit numbers ------------------------------------------------------------------------------

def _base(cx, operand) -> int:
    st = storage(cx, operand)
    return st.addr + (operand.index if isinstance(operand, ir.Byte) else 0)


def _within(cx, index, limit: int, outside: str) -> None:
    """B = the index; to `outside` unless 0 <= index < limit (unsigned compare)."""
    e = cx.e
    s = Scratch(cx.layout.scratch)
    copy_in(cx, index, s.B)
    e.load(s.B[1])
    e.ins("iorwf", s.B[2], W)
    e.ins("iorwf", s.B[3], W)
    e.ins("btfss", e.status, Z)
    e.goto(outside)
    e.ins("movlw", limit)
    e.ins("subwf", s.B[0], W)
    e.ins("btfsc", e.status, C)
    e.goto(outside)


def change_bit(cx, op: ir.ChangeBitOf) -> None:
    e = cx.e
    n = target_size(cx, op.dst)
    base = _base(cx, op.dst)
    if isinstance(op.index, ir.Const):
        k = op.index.value
        if 0 <= k < 8 * n:
            e.ins("bsf" if op.value else "bcf", base + k // 8, k % 8)
        return
    s = Scratch(cx.layout.scratch)
    done, masked = e.new_label("bit"), e.new_label("bit")
    _within(cx, op.index, 8 * n, done)
    # FSR = the byte, E = the bit's mask
    e.ins("rrf", s.B[0], W)
    e.store(s.D)
    e.ins("rrf", s.D, F)
    e.ins("rrf", s.D, W)
    e.ins("andlw", 0x1F)
    e.ins("addlw", base & 0xFF)
    e.store(e.fsr)
    e.point_high(base >> 8)
    e.ins("movlw", 1)
    e.store(s.E)
    e.load(s.B[0])
    e.ins("andlw", 7)
    e.ins("btfsc", e.status, Z)
    e.goto(masked)
    e.store(s.D)
    top = e.new_label("bit")
    e.label(top, loop=True, bound=LoopBound(7, "the mask of a bit number"))
    e.ins("bcf", e.status, C)
    e.ins("rlf", s.E, F)
    e.ins("decfsz", s.D, F)
    e.goto(top)
    e.label(masked)
    if op.value:
        e.load(s.E)
        e.ins("iorwf", e.indf, F)
    else:
        e.ins("comf", s.E, W)
        e.ins("andwf", e.indf, F)
    e.label(done)


def jump_if_bit_of(cx, op: ir.JumpIfBitOf) -> None:
    e = cx.e
    if isinstance(op.index, ir.Const) and not isinstance(op.a, ir.Const):
        found = analysis.constant_bit(op.a, op.index.value, lambda var: storage(cx, var).size)
        if found is None:  # no bit: reads 0
            if not op.value:
                e.goto(op.target)
            return
        bits.jump_if(e, FileBit(_base(cx, op.a) + found[0], found[1]), op.value, op.target)
        return
    s = Scratch(cx.layout.scratch)
    zero, test = e.new_label("bit"), e.new_label("bit")
    copy_in(cx, op.index, s.B)
    e.ins("btfsc", s.B[3], 7)
    e.goto(zero)  # no bit: reads 0
    copy_in(cx, op.a, s.A)
    _count_bits(cx, s)
    e.ins("movf", s.D, F)
    e.ins("btfsc", e.status, Z)
    e.goto(test)
    _repeat(cx, "shr", s.A)
    e.label(test)
    bits.jump_if(e, FileBit(s.A[0], 0), op.value, op.target)
    if op.value:
        e.label(zero)
    else:
        done = e.new_label("bit")
        e.goto(done)
        e.label(zero)
        e.goto(op.target)
        e.label(done)


def _count_bits(cx, s) -> None:
    """D = min(B, 31) for a bit number B that is not negative (past the
    value's 32 bits: its sign bit)."""
    e = cx.e
    have = e.new_label("bit")
    e.load(s.B[1])
    e.ins("iorwf", s.B[2], W)
    e.ins("iorwf", s.B[3], W)
    e.ins("btfss", e.status, Z)
    e.ins("movlw", 0xFF)
    e.ins("iorwf", s.B[0], W)
    e.ins("sublw", 31)
    e.ins("movlw", 31)
    e.ins("btfss", e.status, C)
    e.goto(have)
    e.load(s.B[0])
    e.label(have)
    e.store(s.D)


# --- conversions, tables, bit permutations -----------------------------------------------------

def convert(cx, op: ir.Convert) -> None:
    """The results are unsigned: zero-extended to the destination."""
    e = cx.e
    s = Scratch(cx.layout.scratch)
    w, n = op.width, target_size(cx, op.dst)
    if op.op in ("bin2bcd", "bcd2bin"):
        copy_in(cx, op.src, s.A[:w])
        for reg in s.A[w:]:
            e.ins("clrf", reg)
        e.call(cx.routine(op.op))
        result, width = s.A, 4 if op.op == "bin2bcd" else 2
    elif op.op == "swap":
        result, width = s.B, w
        # one byte: its nibbles; more: the bytes reversed (3 bytes: 0 and 2 swapped)
        for i in range(w):
            put(e, byte(cx, op.src, w - 1 - i), s.B[i])
        if w == 1:
            e.ins("swapf", s.B[0], F)
    else:  # opposite: the bits shifted out of A at the bottom go into B from the bottom
        result, width = s.B, w
        copy_in(cx, op.src, s.A[:w])
        put(e, Byte("const", 8 * w), s.D)
        top = e.new_label("opp")
        e.label(top, loop=True, bound=LoopBound(8 * w, f"OPPOSITE of {w} bytes, one bit a pass"))
        shift_once(e, "sr0", s.A[:w])
        for reg in s.B[:w]:
            e.ins("rlf", reg, F)
        e.ins("decfsz", s.D, F)
        e.goto(top)
    copy_out(cx, widen(cx, result, width, n, False), op.dst)


def table(cx, op: ir.Table) -> None:
    """dst = values[index], one RETLW table per byte of the destination."""
    e = cx.e
    s = Scratch(cx.layout.scratch)
    n = target_size(cx, op.dst)
    copy_in(cx, op.index, s.A[:1 if cx.relative_table(len(op.values)) else 2])
    for address, i in zip(target_bytes(cx, op.dst), range(n)):
        data = bytes((v >> 8 * i) & 0xFF for v in op.values)
        if len(set(data)) == 1:  # every entry's byte the same (a sign extension...): no table
            put(e, Byte("const", data[0]), address)
            continue
        e.call(cx.table(data))
        e.store(address)


def permute(cx, op: ir.Permute) -> None:
    e = cx.e
    s = Scratch(cx.layout.scratch)
    w, n = size(cx, op.src), target_size(cx, op.dst)
    copy_in(cx, op.src, s.B[:w])
    e.ins("clrf", s.A[0])
    for source, dest in op.pairs:
        source = min(source, 8 * w - 1)  # past the width: the sign bit
        e.ins("btfsc", s.B[source // 8], source % 8)
        e.ins("bsf", s.A[0], dest)
    copy_out(cx, widen(cx, s.A, 1, n, False), op.dst)
