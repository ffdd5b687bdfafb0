"""The PIC16 mid-range (14-bit) instruction set as a table: each mnemonic
with its operand pattern, opcode and cycles (instruction cycles of four
clocks). The listing writes the same mnemonics, so gpasm reassembles it to
the same words (tests/test_pic16_encoding.py checks every one).

Operands are plain integers: a file register as its data address (the word
keeps its low 7 bits; STATUS RP1:RP0 pick the bank), d 0 (W) or 1 (F), a bit
number, an 8-bit literal, an 11-bit address within the page.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


class EncodingError(ValueError):
    """An operand out of its instruction's range (a back-end bug)."""


def in_range(value: int, low: int, high: int, what: str) -> int:
    if not low <= value <= high:
        raise EncodingError(f"{what} {value} out of range {low}..{high}")
    return value


def _file(f: int) -> int:
    return in_range(f, 0, 0x1FF, "file register") & 0x7F


@dataclass(frozen=True)
class Spec:
    pattern: str  # "fd", "f", "fb", "k8", "k11", ""
    opcode: int
    cycles: int  # 2 for the instructions that change the PC
    skips: bool = False  # the next instruction may be skipped (one more cycle then)


def _fd(code: int, f: int, d: int) -> int:
    return code | in_range(d, 0, 1, "destination") << 7 | _file(f)


ENCODERS: dict[str, Callable[..., int]] = {
    "fd": _fd,
    "f": lambda code, f: code | _file(f),
    "fb": lambda code, f, b: code | in_range(b, 0, 7, "bit") << 7 | _file(f),
    "k8": lambda code, k: code | (in_range(k, -128, 255, "literal") & 0xFF),
    "k11": lambda code, k: code | in_range(k, 0, 0x7FF, "address"),
    "": lambda code: code,
}

INSTRUCTIONS = {
    "addwf": Spec("fd", 0x0700, 1), "andwf": Spec("fd", 0x0500, 1), "comf": Spec("fd", 0x0900, 1),
    "decf": Spec("fd", 0x0300, 1), "decfsz": Spec("fd", 0x0B00, 1, True), "incf": Spec("fd", 0x0A00, 1),
    "incfsz": Spec("fd", 0x0F00, 1, True), "iorwf": Spec("fd", 0x0400, 1), "movf": Spec("fd", 0x0800, 1),
    "rlf": Spec("fd", 0x0D00, 1), "rrf": Spec("fd", 0x0C00, 1), "subwf": Spec("fd", 0x0200, 1),
    "swapf": Spec("fd", 0x0E00, 1), "xorwf": Spec("fd", 0x0600, 1),
    "clrf": Spec("f", 0x0180, 1), "movwf": Spec("f", 0x0080, 1),
    "clrw": Spec("", 0x0103, 1), "nop": Spec("", 0x0000, 1), "clrwdt": Spec("", 0x0064, 1),
    "retfie": Spec("", 0x0009, 2), "return": Spec("", 0x0008, 2), "sleep": Spec("", 0x0063, 1),
    "bcf": Spec("fb", 0x1000, 1), "bsf": Spec("fb", 0x1400, 1),
    "btfsc": Spec("fb", 0x1800, 1, True), "btfss": Spec("fb", 0x1C00, 1, True),
    "addlw": Spec("k8", 0x3E00, 1), "andlw": Spec("k8", 0x3900, 1), "iorlw": Spec("k8", 0x3800, 1),
    "movlw": Spec("k8", 0x3000, 1), "retlw": Spec("k8", 0x3400, 2), "sublw": Spec("k8", 0x3C00, 1),
    "xorlw": Spec("k8", 0x3A00, 1),
    "call": Spec("k11", 0x2000, 2), "goto": Spec("k11", 0x2800, 2),
}

SKIPS = frozenset(op for op, spec in INSTRUCTIONS.items() if spec.skips)
# after these the next word is not reached by falling through
ENDS = frozenset(("goto", "return", "retlw", "retfie"))


def encode(op: str, *args: int) -> int:
    spec = INSTRUCTIONS[op]
    return ENCODERS[spec.pattern](spec.opcode, *args)

