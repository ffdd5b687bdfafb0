"""The enhanced mid-range PIC16 instruction set (14-bit words: the
PIC12F1840, PIC16F1512...): the mid-range table (compiler/pic16/isa.py)
with the instructions the enhanced core adds, as its datasheets' instruction
set summary gives them. A file register is a data address of up to 12 bits
(32 banks of 128; the word keeps the low 7, BSR supplies the bank).
tests/test_pic16e_encoding.py checks every mnemonic against gpasm.
"""

from __future__ import annotations

from collections.abc import Callable

from .. import isa as midrange
from ..isa import Spec, in_range


def _file(f: int) -> int:
    return in_range(f, 0, 0xFFF, "file register") & 0x7F


ENCODERS: dict[str, Callable[..., int]] = {
    **midrange.ENCODERS,
    "fd": lambda code, f, d: code | in_range(d, 0, 1, "destination") << 7 | _file(f),
    "f": lambda code, f: code | _file(f),
    "fb": lambda code, f, b: code | in_range(b, 0, 7, "bit") << 7 | _file(f),
    "k5": lambda code, k: code | in_range(k, 0, 31, "bank"),
    "k7": lambda code, k: code | in_range(k, 0, 127, "page"),
    "n9": lambda code, n: code | (in_range(n, -256, 255, "offset") & 0x1FF),
}

INSTRUCTIONS = {
    **midrange.INSTRUCTIONS,
    # byte operations through the carry: add with carry, subtract with borrow, shifts
    "addwfc": Spec("fd", 0x3D00, 1), "subwfb": Spec("fd", 0x3B00, 1),
    "lslf": Spec("fd", 0x3500, 1), "lsrf": Spec("fd", 0x3600, 1), "asrf": Spec("fd", 0x3700, 1),
    "movlb": Spec("k5", 0x0020, 1), "movlp": Spec("k7", 0x3180, 1),
    "bra": Spec("n9", 0x3200, 2), "brw": Spec("", 0x000B, 2), "callw": Spec("", 0x000A, 2),
    "reset": Spec("", 0x0001, 1),
}

SKIPS = midrange.SKIPS
FILE_PATTERNS = frozenset(("fd", "f", "fb"))  # the instruction's first operand is a file register
ENDS = midrange.ENDS | {"bra", "brw", "reset"}


def encode(op: str, *args: int) -> int:
    spec = INSTRUCTIONS[op]
    return ENCODERS[spec.pattern](spec.opcode, *args)
