"""The small C functions the generated code calls, each written once here and
copied into a program's file only when its code uses it.

Every integer is computed as `uint32_t` (wrapping is defined there) and
brought back to a signed value of the destination's width by `ld_sext`, so no
operation of the generated code has undefined or implementation-defined
behaviour, whatever the compiler's `int` is (16 bits on AVR).
"""

from __future__ import annotations

HELPERS: dict[str, tuple[tuple[str, ...], str]] = {
    # name: (helpers it calls, its definition)
    "ld_mask": ((), """\
static uint32_t ld_mask(int bits)
{
    return bits >= 32 ? UINT32_C(0xFFFFFFFF) : (UINT32_C(1) << bits) - 1u;
}"""),
    "ld_sext": (("ld_mask",), """\
/* The low `bits` bits of v as a signed value. */
static int32_t ld_sext(uint32_t v, int bits)
{
    uint32_t mask = ld_mask(bits);
    uint32_t sign = (UINT32_C(1) << (bits - 1));
    v &= mask;
    return (v & sign) ? -(int32_t)(mask - v) - 1 : (int32_t)v;
}"""),
    "ld_fits": ((), """\
/* Whether v fits a signed variable of `bits` bits (ADD/SUB set ROverflowFlagV when not). */
static int ld_fits(int64_t v, int bits)
{
    int64_t half = (int64_t)1 << (bits - 1);
    return v >= -half && v < half;
}"""),
    "ld_bit": ((), """\
/* Bit i of a: none below 0, the sign bit past the width (a is sign-extended). */
static int ld_bit(int32_t a, int32_t i)
{
    if (i < 0) {
        return 0;
    }
    if (i > 31) {
        i = 31;
    }
    return (int)(((uint32_t)a >> i) & 1u);
}"""),
    "ld_shl": (("ld_mask",), """\
/* LDmicro shifts one bit at a time: a negative count shifts nothing, one past the width everything out. */
static uint32_t ld_shl(uint32_t v, int32_t n, int bits)
{
    if (n < 0) {
        n = 0;
    }
    return n >= bits ? 0u : (v << n) & ld_mask(bits);
}"""),
    "ld_sr0": (("ld_mask",), """\
static uint32_t ld_sr0(uint32_t v, int32_t n, int bits)
{
    if (n < 0) {
        n = 0;
    }
    return n >= bits ? 0u : (v & ld_mask(bits)) >> n;
}"""),
    "ld_shr": ((), """\
/* Arithmetic shift right of a signed value, written with unsigned operations. */
static uint32_t ld_shr(int32_t v, int32_t n)
{
    uint32_t u = (uint32_t)v;
    if (n < 0) {
        n = 0;
    }
    if (n > 31) {
        n = 31;
    }
    return v < 0 ? ~(~u >> n) : u >> n;
}"""),
    "ld_rol": (("ld_mask",), """\
static uint32_t ld_rol(uint32_t v, int32_t n, int bits)
{
    uint32_t mask = ld_mask(bits);
    v &= mask;
    if (n < 0) {
        n = 0;
    }
    n %= bits;
    return n == 0 ? v : ((v << n) | (v >> (bits - n))) & mask;
}"""),
    "ld_ror": (("ld_rol",), """\
/* Right by n is left by the rest of the width. */
static uint32_t ld_ror(uint32_t v, int32_t n, int bits)
{
    if (n < 0) {
        n = 0;
    }
    return ld_rol(v, bits - n % bits, bits);
}"""),
    "ld_bin2bcd": ((), """\
/* Unpacked BCD, one decimal digit per byte, of 0..9999. */
static uint32_t ld_bin2bcd(int32_t v)
{
    uint32_t result = 0;
    int position;
    for (position = 0; position < 4; position++) {
        result |= (uint32_t)(v % 10) << (8 * position);
        v /= 10;
    }
    return result;
}"""),
    "ld_bcd_ok": ((), """\
static int ld_bcd_ok(uint32_t v)
{
    int position;
    for (position = 0; position < 4; position++) {
        if (((v >> (8 * position)) & 0x0Fu) > 9u) {
            return 0;
        }
    }
    return 1;
}"""),
    "ld_bcd2bin": ((), """\
static uint32_t ld_bcd2bin(uint32_t v)
{
    return (v & 0x0Fu) + ((v >> 8) & 0x0Fu) * 10u + ((v >> 16) & 0x0Fu) * 100u + ((v >> 24) & 0x0Fu) * 1000u;
}"""),
    "ld_swap": ((), """\
/* 1 byte: its nibbles; 2: its bytes; 3: bytes 0 and 2; 4: all four reversed. */
static uint32_t ld_swap(uint32_t v, int bytes)
{
    uint32_t b0 = v & 0xFFu, b1 = (v >> 8) & 0xFFu, b2 = (v >> 16) & 0xFFu, b3 = (v >> 24) & 0xFFu;
    switch (bytes) {
    case 1:
        return ((b0 & 0x0Fu) << 4) | (b0 >> 4);
    case 2:
        return (b0 << 8) | b1;
    case 3:
        return (b0 << 16) | (b1 << 8) | b2;
    default:
        return (b0 << 24) | (b1 << 16) | (b2 << 8) | b3;
    }
}"""),
    "ld_opposite": ((), """\
/* The low `bits` bits in reverse order. */
static uint32_t ld_opposite(uint32_t v, int bits)
{
    uint32_t result = 0;
    int i;
    for (i = 0; i < bits; i++) {
        result = (result << 1) | ((v >> i) & 1u);
    }
    return result;
}"""),
}


def helper_text(used: set[str]) -> str:
    """The definitions of `used` and of what they call, in a fixed order."""
    wanted: set[str] = set()
    pending = list(used)
    while pending:
        name = pending.pop()
        if name not in wanted:
            wanted.add(name)
            pending.extend(HELPERS[name][0])
    return "\n\n".join(text for name, (_, text) in HELPERS.items() if name in wanted)
