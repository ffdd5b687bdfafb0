"""Integer arithmetic as LDmicro's compiled code does it: signed two's
complement variables of 1 to 4 bytes, C division, BCD, byte swaps, shifts
within the operand's width, and the 7-segment font."""

from __future__ import annotations


def byte_needed(value: int) -> int:
    """Bytes a signed variable needs to hold `value` (LDmicro's byteNeeded)."""
    for size in (1, 2, 3):
        if -(1 << (8 * size - 1)) <= value < (1 << (8 * size - 1)):
            return size
    return 4


def wrap(value: int, size: int) -> int:
    half = 1 << (8 * size - 1)
    return ((value + half) & ((half << 1) - 1)) - half


def wrap_expr(expr: str, size: int) -> str:
    """Python source wrapping `expr` to a signed variable of `size` bytes."""
    half = 1 << (8 * size - 1)
    return f"(({expr}) + {half} & {(half << 1) - 1}) - {half}"


def cdiv(a: int, b: int) -> int:
    """C division: truncates toward zero."""
    q = abs(a) // abs(b)
    return q if (a < 0) == (b < 0) else -q


def cmod(a: int, b: int) -> int:
    """C remainder: the sign of the dividend."""
    return a - cdiv(a, b) * b


def shift(op: str, value: int, count: int, size: int) -> int:
    """SHL/SHR/SR0/ROL/ROR within 8*size bits. LDmicro shifts one bit at a
    time `count` times, so a negative count shifts nothing and a count past
    the width shifts everything out (rotations go round)."""
    bits = 8 * size
    mask = (1 << bits) - 1
    count = max(count, 0)
    if op == "SHR":
        return value >> min(count, bits)
    unsigned = value & mask
    if op == "SHL":
        return (unsigned << min(count, bits)) & mask
    if op == "SR0":
        return unsigned >> min(count, bits)
    count %= bits
    if op == "ROL":
        return ((unsigned << count) | (unsigned >> (bits - count))) & mask
    return ((unsigned >> count) | (unsigned << (bits - count))) & mask


def bin2bcd(value: int) -> int | None:
    """Unpacked BCD, one decimal digit per byte; None if not 0..9999."""
    if not 0 <= value <= 9999:
        return None
    result = 0
    for position in range(4):
        result |= (value % 10) << (8 * position)
        value //= 10
    return result


def bcd2bin(value: int) -> int | None:
    """The inverse of bin2bcd (low nibble of each byte); None if a digit > 9."""
    digits = [(value >> (8 * position)) & 0x0F for position in range(4)]
    if any(d > 9 for d in digits):
        return None
    return digits[0] + digits[1] * 10 + digits[2] * 100 + digits[3] * 1000


def swap(value: int, size: int) -> int:
    """1 byte: swap nibbles; 2: swap bytes; 3: swap bytes 0 and 2; 4: reverse."""
    if size == 1:
        return ((value & 0x0F) << 4) | ((value & 0xF0) >> 4)
    data = (value & ((1 << (8 * size)) - 1)).to_bytes(size, "little")
    if size == 3:
        return int.from_bytes(bytes((data[2], data[1], data[0])), "little")
    return int.from_bytes(data[::-1], "little")


def opposite(value: int, size: int) -> int:
    """The bits of the value in reverse order over 8*size bits."""
    bits = 8 * size
    text = format(value & ((1 << bits) - 1), f"0{bits}b")
    return int(text[::-1], 2)


def bit_mask(bit: int) -> int:
    """1 << bit for SET_BIT/CLEAR_BIT/IF_BIT_*; a negative bit number selects no bit.
    No variable is wider than 32 bits, so a bit number past 63 acts as 63: it
    reads the sign and writes nothing, without a mask of a billion bits."""
    return 1 << min(bit, 63) if bit >= 0 else 0


# LDmicro's 7-segment font (display.cpp `char7seg`, as its compiled code
# stores it): bits DP g f e d c b a = 7..0, indexed by ASCII code 0x00-0x7F
# (0x00-0x0F show the hex digits, 0x10-0x1F the same with the point), and
# index 128 the degree sign, selected by the character code 0xB0.
CHAR7SEG = (
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
    0xBF, 0x86, 0xDB, 0xCF, 0xE6, 0xED, 0xFD, 0x87, 0xFF, 0xEF, 0xF7, 0xFC, 0xB9, 0xDE, 0xF9, 0xF1,
    0x00, 0xB0, 0x22, 0x4E, 0x6D, 0xD2, 0xDA, 0x20, 0x39, 0x0F, 0x72, 0x70, 0x0C, 0x40, 0x80, 0x52,
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x09, 0x0D, 0x61, 0x41, 0x43, 0xD3,
    0x9F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71, 0x3D, 0x74, 0x30, 0x1E, 0x75, 0x38, 0x55, 0x54, 0x5C,
    0x73, 0x67, 0x33, 0x6D, 0x78, 0x3E, 0x1C, 0x6A, 0x76, 0x6E, 0x5B, 0x39, 0x64, 0x0F, 0x23, 0x08,
    0x20, 0x5F, 0x7C, 0x58, 0x5E, 0x7B, 0x71, 0x6F, 0x74, 0x10, 0x0E, 0x75, 0x18, 0x55, 0x54, 0x5C,
    0x73, 0x67, 0x50, 0x6D, 0x78, 0x3E, 0x1C, 0x6A, 0x76, 0x6E, 0x5B, 0x39, 0x30, 0x0F, 0x01, 0x00,
    0x63,
)
DEGREE_CHAR = 0xB0
DEGREE_INDEX = 128


def seg7_index(code: int) -> int:
    """The font index LDmicro's code uses for a character code: the degree
    sign for 0xB0, a blank for anything outside the table."""
    if code == DEGREE_CHAR:
        return DEGREE_INDEX
    if code < 0 or code >= len(CHAR7SEG):
        return 0x20
    return code
