"""The baseline (12-bit) instruction set of the PIC10F200/202 as a table:
its 33 instructions, each with its operand pattern, opcode and cycles
(instruction cycles of four clocks). The listing writes the same mnemonics,
so gpasm reassembles it to the same words (tests/test_pic10_compiler.py).

Operands are plain integers: a file register as its data address (5 bits:
the PIC10F20x has one bank of 32), d 0 (W) or 1 (F), a bit number, an 8-bit
literal, a 9-bit GOTO address, an 8-bit CALL address (a CALL reaches only
the first 256 words: bit 8 of the PC is cleared), the port of TRIS (6: GPIO).

What the mid-range has and the baseline has not: ADDLW, SUBLW, RETURN,
RETFIE and interrupts; OPTION and TRIS are instructions, not registers.
"""

from __future__ import annotations

from collections.abc import Callable

from ..pic16.isa import Spec, in_range


def _fd(code: int, f: int, d: int) -> int:
    return code | in_range(d, 0, 1, "destination") << 5 | in_range(f, 0, 0x1F, "file register")


ENCODERS: dict[str, Callable[..., int]] = {
    "fd": _fd,
    "f": lambda code, f: code | in_range(f, 0, 0x1F, "file register"),
    "fb": lambda code, f, b: code | in_range(b, 0, 7, "bit") << 5 | in_range(f, 0, 0x1F, "file register"),
    "k8": lambda code, k: code | (in_range(k, -128, 255, "literal") & 0xFF),
    "k9": lambda code, k: code | in_range(k, 0, 0x1FF, "address"),
    "c8": lambda code, k: code | in_range(k, 0, 0xFF, "call address"),
    "t": lambda code, f: code | in_range(f, 5, 7, "port"),
    "": lambda code: code,
}

INSTRUCTIONS = {
    "addwf": Spec("fd", 0x1C0, 1), "andwf": Spec("fd", 0x140, 1), "comf": Spec("fd", 0x240, 1),
    "decf": Spec("fd", 0x0C0, 1), "decfsz": Spec("fd", 0x2C0, 1, True), "incf": Spec("fd", 0x280, 1),
    "incfsz": Spec("fd", 0x3C0, 1, True), "iorwf": Spec("fd", 0x100, 1), "movf": Spec("fd", 0x200, 1),
    "rlf": Spec("fd", 0x340, 1), "rrf": Spec("fd", 0x300, 1), "subwf": Spec("fd", 0x080, 1),
    "swapf": Spec("fd", 0x380, 1), "xorwf": Spec("fd", 0x180, 1),
    "clrf": Spec("f", 0x060, 1), "movwf": Spec("f", 0x020, 1),
    "clrw": Spec("", 0x040, 1), "nop": Spec("", 0x000, 1), "clrwdt": Spec("", 0x004, 1),
    "option": Spec("", 0x002, 1), "sleep": Spec("", 0x003, 1), "tris": Spec("t", 0x000, 1),
    "bcf": Spec("fb", 0x400, 1), "bsf": Spec("fb", 0x500, 1),
    "btfsc": Spec("fb", 0x600, 1, True), "btfss": Spec("fb", 0x700, 1, True),
    "andlw": Spec("k8", 0xE00, 1), "iorlw": Spec("k8", 0xD00, 1), "movlw": Spec("k8", 0xC00, 1),
    "retlw": Spec("k8", 0x800, 2), "xorlw": Spec("k8", 0xF00, 1),
    "call": Spec("c8", 0x900, 2), "goto": Spec("k9", 0xA00, 2),
}

SKIPS = frozenset(op for op, spec in INSTRUCTIONS.items() if spec.skips)
ENDS = frozenset(("goto", "retlw"))  # after these the next word is not reached by falling through


def encode(op: str, *args: int) -> int:
    spec = INSTRUCTIONS[op]
    return ENCODERS[spec.pattern](spec.opcode, *args)
