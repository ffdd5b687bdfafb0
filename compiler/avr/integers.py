"""Integer patterns: operands are loaded into A (and B) sign-extended to the
width the operation needs, computed byte by byte low to high, and the low
bytes stored to the destination (the wrap-around the semantics ask for).

| operation            | pattern                                                  |
|----------------------|----------------------------------------------------------|
| x + k, x - k         | SUBI/SBCI with the (negated) constant                     |
| x op y               | ADD/ADC, SUB/SBC, AND, OR, EOR byte by byte               |
| x & k, x | k         | ANDI/ORI, skipping bytes the constant leaves alone       |
| x * y                | MUL (1 and 2 bytes), the mul32 routine (3 and 4)          |
| x / y, x % y         | the signed divmod16/divmod32 routines                     |
| x <rel> y            | CPI/CPC or CP/CPC, then BREQ/BRNE/BRLT/BRGE               |
| shifts               | one LSL/ROL.. (ASR, LSR, ROR) chain per bit, in a loop   |
"""

from __future__ import annotations

from lang.numbers import wrap
from lang.semantics import ir

from .. import analysis
from ..analysis import value_size
from ..image import LoopBound
from . import bits
from .emit import SCRATCH, A, B
from .memory import MemBit, RegBit

REMAINDER = (26, 27, 28, 29)  # where the divide routines leave the remainder


def storage(cx, operand):
    var = operand.var if isinstance(operand, ir.Byte) else operand
    return cx.layout.vars[var.name]


def size(cx, operand) -> int:
    """Bytes that hold the operand's value as a signed number."""
    return value_size(operand, lambda var: storage(cx, var).size)


def target_size(cx, target) -> int:
    return analysis.target_size(target, lambda var: storage(cx, var).size)


def extend(cx, regs, n: int, signed: bool = True) -> None:
    """regs[n:] = the sign (or zero) extension of regs[:n]."""
    e = cx.e
    if len(regs) <= n:
        return
    if signed:
        e.ins("mov", regs[n], regs[n - 1])
        e.ins("lsl", regs[n])
        e.ins("sbc", regs[n], regs[n])
        fill = regs[n]
        rest = regs[n + 1:]
    else:
        fill, rest = e.zero, regs[n:]
    for reg in rest:
        e.ins("mov", reg, fill)


def load(cx, operand, regs) -> None:
    """regs = the operand's value, sign-extended or truncated to len(regs) bytes."""
    e = cx.e
    if isinstance(operand, ir.Const):
        for i, reg in enumerate(regs):
            e.constant((operand.value >> 8 * i) & 0xFF, reg)
        return
    st = storage(cx, operand)
    if isinstance(operand, ir.Byte):
        if operand.index < st.size:
            e.load_byte(st.addr + operand.index, regs[0], st.ram)
        else:  # past the variable: its sign byte
            e.load_byte(st.addr + st.size - 1, regs[0], st.ram)
            e.ins("lsl", regs[0])
            e.ins("sbc", regs[0], regs[0])
        extend(cx, regs, 1, signed=False)
        return
    n = min(len(regs), st.size)
    for i in range(n):
        e.load_byte(st.addr + i, regs[i], st.ram)
    extend(cx, regs, n)


def store(cx, target, regs) -> None:
    """The low bytes of regs into the target (regs must be at least as wide)."""
    st = storage(cx, target)
    if isinstance(target, ir.Byte):
        cx.e.store_byte(st.addr + target.index, regs[0], st.ram)
        return
    for i in range(st.size):
        cx.e.store_byte(st.addr + i, regs[i], st.ram)


def move(cx, op: ir.Move) -> None:
    n = target_size(cx, op.dst)
    if isinstance(op.src, ir.Const):
        st = storage(cx, op.dst)
        base = st.addr + (op.dst.index if isinstance(op.dst, ir.Byte) else 0)
        for i in range(n):
            cx.e.store_byte(base + i, cx.e.constant_reg((op.src.value >> 8 * i) & 0xFF), st.ram)
        return
    load(cx, op.src, A[:n])
    store(cx, op.dst, A[:n])


_CHAINS = {"add": ("add", "adc"), "sub": ("sub", "sbc"), "and": ("and_", "and_"), "or": ("or_", "or_"),
           "xor": ("eor", "eor")}


def arith(cx, op: ir.Arith) -> None:
    e = cx.e
    n = target_size(cx, op.dst)
    if op.op == "mul":
        _multiply(cx, op, n)
        return
    width = max(n, size(cx, op.a), size(cx, op.b)) if op.overflow else n
    r = A[:width]
    load(cx, op.a, r)
    b = op.b
    if isinstance(b, ir.Const) and op.op in ("add", "sub") and not op.overflow:
        k = wrap(b.value if op.op == "sub" else -b.value, width)
        if k:
            for i, reg in enumerate(r):
                e.ins("subi" if i == 0 else "sbci", reg, (k >> 8 * i) & 0xFF)
    elif isinstance(b, ir.Const) and op.op in ("and", "or"):
        for i, reg in enumerate(r):
            byte = (b.value >> 8 * i) & 0xFF
            if op.op == "and" and byte != 0xFF:
                e.ins("andi", reg, byte)
            elif op.op == "or" and byte:
                e.ins("ori", reg, byte)
    else:
        load(cx, b, B[:width])
        first, rest = _CHAINS[op.op]
        for i, reg in enumerate(r):
            e.ins(first if i == 0 else rest, reg, B[i])
    if op.overflow:
        _overflow(cx, r, n, op.overflow)
    store(cx, op.dst, r)


def _overflow(cx, r, n: int, flag: ir.Bit) -> None:
    """Set the flag when the sum does not fit n bytes: the hardware's V flag
    for the width computed, and the bytes above n not the sign extension."""
    e = cx.e
    overflow, done = e.new_label(), e.new_label()
    e.branch("brvs", overflow)
    if len(r) > n:
        e.ins("mov", SCRATCH, r[n - 1])
        e.ins("lsl", SCRATCH)
        e.ins("sbc", SCRATCH, SCRATCH)
        for reg in r[n:]:
            e.ins("cp", reg, SCRATCH)
            e.branch("brne", overflow)
    e.jump(done)
    e.label(overflow)
    bits.write(e, cx.bit(flag), True)
    e.label(done)


def _multiply(cx, op: ir.Arith, n: int) -> None:
    e = cx.e
    if n <= 2 and cx.part.has_mul:
        load(cx, op.a, A[:n])
        load(cx, op.b, B[:n])
        e.ins("mul", A[0], B[0])
        if n == 1:
            e.ins("mov", A[0], 0)
        else:
            # the low 16 bits of the product: a0*b0 + (a1*b0 + a0*b1) << 8
            e.ins("movw", SCRATCH, 0)
            e.ins("mul", A[1], B[0])
            e.ins("add", SCRATCH + 1, 0)
            e.ins("mul", A[0], B[1])
            e.ins("add", SCRATCH + 1, 0)
            e.ins("movw", A[0], SCRATCH)
    else:
        load(cx, op.a, A)
        load(cx, op.b, B)
        e.call(cx.routine("mul32"))
    store(cx, op.dst, A[:n])


def divide(cx, op: ir.Divide) -> None:
    n = target_size(cx, op.dst)
    widest = max(n, size(cx, op.a), size(cx, op.b), target_size(cx, op.remainder) if op.remainder else 1)
    width = 2 if widest <= 2 else 4
    load(cx, op.a, A[:width])
    load(cx, op.b, B[:width])
    cx.e.call(cx.routine(f"divmod{8 * width}"))
    if op.remainder is not None:
        store(cx, op.remainder, REMAINDER[:target_size(cx, op.remainder)])
    store(cx, op.dst, (A if op.op == "div" else REMAINDER)[:n])


def unary(cx, op: ir.Unary) -> None:
    e = cx.e
    n = target_size(cx, op.dst)
    r = A[:n]
    load(cx, op.a, r)
    if op.op == "neg" and n == 1:
        e.ins("neg", r[0])
    else:
        for reg in r:
            e.ins("com", reg)
        if op.op == "neg":
            for i, reg in enumerate(r):
                e.ins("subi" if i == 0 else "sbci", reg, 0xFF)
    store(cx, op.dst, r)


_BRANCH = {"==": "breq", "!=": "brne", "<": "brlt", ">=": "brge"}
_SWAPPED = {"==": "==", "!=": "!=", "<": ">", ">": "<", "<=": ">=", ">=": "<="}


def compare_jump(cx, op: ir.JumpIf) -> None:
    e = cx.e
    a, rel, b = op.a, op.rel, op.b
    if isinstance(a, ir.Const):
        a, b, rel = b, a, _SWAPPED[rel]
    if rel in (">", "<="):
        if isinstance(b, ir.Const):
            # x > k is x >= k+1, x <= k is x < k+1
            b, rel = ir.Const(b.value + 1), ">=" if rel == ">" else "<"
        else:
            a, b, rel = b, a, _SWAPPED[rel]
    width = max(size(cx, a), size(cx, b))
    r = A[:width]
    load(cx, a, r)
    if isinstance(b, ir.Const):
        for i, reg in enumerate(r):
            byte = (b.value >> 8 * i) & 0xFF
            if i == 0:
                e.ins("cpi", reg, byte)
            else:
                e.ins("cpc", reg, e.constant_reg(byte))
    else:
        load(cx, b, B[:width])
        for i, reg in enumerate(r):
            e.ins("cp" if i == 0 else "cpc", reg, B[i])
    e.branch(_BRANCH[rel], op.target)


# --- shifts ------------------------------------------------------------------------------

def _shift_once(cx, kind: str, r) -> None:
    e = cx.e
    if kind in ("shl", "rol"):
        e.ins("lsl", r[0])
        for reg in r[1:]:
            e.ins("rol", reg)
        if kind == "rol":
            e.ins("adc", r[0], e.zero)  # the bit shifted out comes back in at bit 0
        return
    if kind == "ror":
        e.ins("bst", r[0], 0)
    e.ins("asr" if kind == "shr" else "lsr", r[-1])
    for reg in reversed(r[:-1]):
        e.ins("ror", reg)
    if kind == "ror":
        e.ins("bld", r[-1], 7)


def shift(cx, op: ir.Shift) -> None:
    e = cx.e
    w, n = op.width, target_size(cx, op.dst)
    r = A[:w]
    load(cx, op.a, r)
    bits_ = 8 * w
    rotate = op.op in ("rol", "ror")
    if isinstance(op.count, ir.Const):
        count = op.count.value % bits_ if rotate else min(max(op.count.value, 0), bits_)
        if count * w <= 16:
            for _ in range(count):
                _shift_once(cx, op.op, r)
        else:
            e.constant(count, SCRATCH)
            _loop(cx, op.op, r, SCRATCH, count)
    else:
        done = e.new_label()
        load(cx, op.count, B)
        e.ins("tst", B[3])
        e.branch("brmi", done)  # a negative count shifts nothing
        if rotate:
            _modulo(cx, bits_)
        else:
            within = e.new_label()
            e.ins("cpi", B[0], bits_)
            for reg in B[1:]:
                e.ins("cpc", reg, e.zero)
            e.branch("brcs", within)
            e.constant(bits_, B[0])
            e.label(within)
        e.ins("tst", B[0])
        e.branch("breq", done)
        _loop(cx, op.op, r, B[0], bits_)
        e.label(done)
    extend(cx, A[:max(w, n)], w, signed=op.op == "shr")
    store(cx, op.dst, A[:max(w, n)])


def _loop(cx, kind: str, r, counter: int, passes: int) -> None:
    """Shift `counter` times (1 to `passes`)."""
    e = cx.e
    top = e.new_label()
    e.label(top, loop=True, bound=LoopBound(passes, f"a shift of {len(r)} bytes, one bit a pass"))
    _shift_once(cx, kind, r)
    e.ins("dec", counter)
    e.branch("brne", top)


def _modulo(cx, bits_: int) -> None:
    """B0 = B mod bits_ (B not negative)."""
    e = cx.e
    if bits_ & (bits_ - 1) == 0:
        e.ins("andi", B[0], bits_ - 1)
        return
    for reg in A:
        e.ins("push", reg)
    for src, dst in zip(B, A):
        e.ins("mov", dst, src)
    for reg, byte in zip(B, (bits_, 0, 0, 0)):
        e.constant(byte, reg)
    e.call(cx.routine("udivmod32"))
    e.ins("mov", B[0], REMAINDER[0])
    for reg in reversed(A):
        e.ins("pop", reg)


# --- bit numbers ----------------------------------------------------------------------------

def change_bit(cx, op: ir.ChangeBitOf) -> None:
    e = cx.e
    st = storage(cx, op.dst)
    n = target_size(cx, op.dst)
    base = st.addr + (op.dst.index if isinstance(op.dst, ir.Byte) else 0)
    if isinstance(op.index, ir.Const):
        k = op.index.value
        if 0 <= k < 8 * n:
            e.load_byte(base + k // 8, SCRATCH, st.ram)
            mask = 1 << (k % 8)
            e.ins("ori" if op.value else "andi", SCRATCH, mask if op.value else ~mask & 0xFF)
            e.store_byte(base + k // 8, SCRATCH, st.ram)
        return
    done = e.new_label()
    load(cx, op.index, B)
    e.ins("cpi", B[0], 8 * n)  # unsigned: a negative number is out of range too
    for reg in B[1:]:
        e.ins("cpc", reg, e.zero)
    e.branch("brcc", done)
    _mask_and_pointer(cx, base)
    e.ins("ld_x", A[0])
    if op.value:
        e.ins("or_", A[0], A[1])
    else:
        e.ins("com", A[1])
        e.ins("and_", A[0], A[1])
    e.ins("st_x", A[0])
    e.forget_scratch()
    e.label(done)


def _mask_and_pointer(cx, base: int) -> None:
    """From a bit number in B0: X = base + B0/8, A1 = 1 << (B0 % 8)."""
    e = cx.e
    e.ins("mov", A[0], B[0])
    e.ins("lsr", A[0])
    e.ins("lsr", A[0])
    e.ins("lsr", A[0])
    e.constant(base & 0xFF, 26)
    e.constant(base >> 8, 27)
    e.ins("add", 26, A[0])
    e.ins("adc", 27, e.zero)
    e.ins("andi", B[0], 7)
    e.constant(1, A[1])
    top, done = e.new_label(), e.new_label()
    e.branch("breq", done)
    e.label(top, loop=True, bound=LoopBound(7, "the mask of a bit number"))
    e.ins("lsl", A[1])
    e.ins("dec", B[0])
    e.branch("brne", top)
    e.label(done)


def jump_if_bit_of(cx, op: ir.JumpIfBitOf) -> None:
    e = cx.e
    if isinstance(op.index, ir.Const) and not isinstance(op.a, ir.Const):
        st = storage(cx, op.a)
        found = analysis.constant_bit(op.a, op.index.value, lambda var: storage(cx, var).size)
        if found is None:  # no bit: reads 0
            if not op.value:
                e.jump(op.target)
            return
        base = st.addr + (op.a.index if isinstance(op.a, ir.Byte) else 0)
        bits.jump_if(e, MemBit(base + found[0], found[1], st.ram), op.value, op.target)
        return
    zero, test, done = e.new_label(), e.new_label(), e.new_label()
    load(cx, op.a, A)
    load(cx, op.index, B)
    e.ins("tst", B[3])
    e.branch("brmi", zero)  # no bit: reads 0
    e.ins("cpi", B[0], 32)
    for reg in B[1:]:
        e.ins("cpc", reg, e.zero)
    within = e.new_label()
    e.branch("brcs", within)
    e.constant(31, B[0])  # past the value: its sign bit
    e.label(within)
    e.ins("tst", B[0])
    e.branch("breq", test)
    _loop(cx, "shr", A, B[0], 31)
    e.label(test)
    bits.jump_if(e, RegBit(A[0], 0), op.value, op.target)
    e.jump(done)
    e.label(zero)
    if not op.value:
        e.jump(op.target)
    e.label(done)


# --- conversions, tables, bit permutations ---------------------------------------------------

def convert(cx, op: ir.Convert) -> None:
    """The results are unsigned: zero-extended to the destination."""
    e = cx.e
    w, n = op.width, target_size(cx, op.dst)
    load(cx, op.src, A[:w])
    result, width = A, w
    if op.op in ("bin2bcd", "bcd2bin"):
        e.call(cx.routine(op.op))
        width = 4 if op.op == "bin2bcd" else 2
    elif op.op == "swap":
        if w == 1:
            e.ins("swap", A[0])
        for i in range(w // 2):
            e.ins("mov", SCRATCH, A[i])
            e.ins("mov", A[i], A[w - 1 - i])
            e.ins("mov", A[w - 1 - i], SCRATCH)
    else:  # opposite: the bits shifted out of A at the bottom go into B from the bottom
        e.constant(8 * w, SCRATCH)
        top = e.new_label()
        e.label(top, loop=True, bound=LoopBound(8 * w, f"OPPOSITE of {w} bytes, one bit a pass"))
        e.ins("lsr", A[w - 1])
        for reg in reversed(A[:w - 1]):
            e.ins("ror", reg)
        for reg in B[:w]:
            e.ins("rol", reg)
        e.ins("dec", SCRATCH)
        e.branch("brne", top)
        result = B
    extend(cx, result[:max(width, n)], width, signed=False)
    store(cx, op.dst, result[:max(width, n)])


def table(cx, op: ir.Table) -> None:
    e = cx.e
    n = target_size(cx, op.dst)
    data = b"".join((v & ((1 << 8 * n) - 1)).to_bytes(n, "little") for v in op.values)
    label = cx.table(data)
    load(cx, op.index, (30, 31))
    if n in (2, 4):
        for _ in range(n // 2):
            e.ins("lsl", 30)
            e.ins("rol", 31)
    elif n == 3:
        e.pair(26, 30)
        e.ins("lsl", 30)
        e.ins("rol", 31)
        e.ins("add", 30, 26)
        e.ins("adc", 31, 27)
    e.load_address(26, 27, label)
    e.ins("add", 30, 26)
    e.ins("adc", 31, 27)
    for reg in A[:n]:
        e.ins("lpm_p" if e.core.flash_data is None else "ld_zp", reg)
    store(cx, op.dst, A[:n])


def permute(cx, op: ir.Permute) -> None:
    e = cx.e
    w, n = size(cx, op.src), target_size(cx, op.dst)
    load(cx, op.src, B[:w])
    e.ins("mov", A[0], e.zero)
    for source, dest in op.pairs:
        source = min(source, 8 * w - 1)  # past the width: the sign bit
        e.ins("sbrc", B[source // 8], source % 8)
        e.ins("ori", A[0], 1 << dest)
    extend(cx, A[:n], 1, signed=False)
    store(cx, op.dst, A[:n])
