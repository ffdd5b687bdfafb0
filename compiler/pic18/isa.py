"""The PIC18 instruction set (16-bit words) as a table: each mnemonic with its
operand pattern, opcode, words and cycles. The listing writes the same
mnemonics, so gpasm reassembles it to the same words
(tests/test_pic18_encoding.py checks every one).

The shared patterns (compiler/pic16/) write the mid-range mnemonics; the two
whose PIC18 names differ are `ALIASES` (RLF is RLCF, RRF is RRCF: both
rotate through the carry).

Operands are plain integers: a file register as its 12-bit data address (the
word keeps its low 8 bits, with a = 0 for the access bank: RAM 0x000-0x07F
and the SFRs 0xF80-0xFFF; otherwise a = 1 and BSR supplies the high 4 bits),
d 0 (W) or 1 (F), a bit number, an 8-bit literal, a word offset (BZ...,
BRA, RCALL) or a word address (GOTO, CALL).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..pic16.isa import in_range

ACCESS_RAM_END = 0x80  # RAM below it and SFRs from ACCESS_SFR on need no BSR
ACCESS_SFR = 0xF80
ALIASES = {"rlf": "rlcf", "rrf": "rrcf"}


def access(f: int) -> int:
    """The instruction's a bit: 0 for the access bank, 1 through BSR."""
    in_range(f, 0, 0xFFF, "file register")
    return 0 if f < ACCESS_RAM_END or f >= ACCESS_SFR else 1


def _f(f: int) -> int:
    return access(f) << 8 | f & 0xFF


@dataclass(frozen=True)
class Spec:
    pattern: str  # "fd", "f", "fb", "k8", "k4", "n8", "n11", "k20", "ff", ""
    opcode: int
    cycles: int = 1  # 2 for the instructions that change the PC (and the two-word moves)
    skips: bool = False  # may skip the next instruction (one more cycle, two over a two-word one)

    @property
    def words(self) -> int:
        return 2 if self.pattern in ("k20", "ff") else 1


ENCODERS: dict[str, Callable[..., tuple[int, ...]]] = {
    "fd": lambda code, f, d: (code | in_range(d, 0, 1, "destination") << 9 | _f(f),),
    "f": lambda code, f: (code | _f(f),),
    "fb": lambda code, f, b: (code | in_range(b, 0, 7, "bit") << 9 | _f(f),),
    "k8": lambda code, k: (code | (in_range(k, -128, 255, "literal") & 0xFF),),
    "k4": lambda code, k: (code | in_range(k, 0, 15, "bank"),),
    "n8": lambda code, n: (code | (in_range(n, -128, 127, "offset") & 0xFF),),
    "n11": lambda code, n: (code | (in_range(n, -1024, 1023, "offset") & 0x7FF),),
    "k20": lambda code, k: (code | (in_range(k, 0, 0xFFFFF, "address") & 0xFF), 0xF000 | k >> 8),
    "ff": lambda code, src, dst: (code | in_range(src, 0, 0xFFF, "file register"),
                                  0xF000 | in_range(dst, 0, 0xFFF, "file register")),
    "": lambda code: (code,),
}

INSTRUCTIONS = {
    "addwf": Spec("fd", 0x2400), "addwfc": Spec("fd", 0x2000), "andwf": Spec("fd", 0x1400),
    "comf": Spec("fd", 0x1C00), "decf": Spec("fd", 0x0400), "decfsz": Spec("fd", 0x2C00, skips=True),
    "incf": Spec("fd", 0x2800), "incfsz": Spec("fd", 0x3C00, skips=True), "iorwf": Spec("fd", 0x1000),
    "movf": Spec("fd", 0x5000), "rlcf": Spec("fd", 0x3400), "rrcf": Spec("fd", 0x3000),
    "subwf": Spec("fd", 0x5C00), "swapf": Spec("fd", 0x3800), "xorwf": Spec("fd", 0x1800),
    "clrf": Spec("f", 0x6A00), "movwf": Spec("f", 0x6E00), "mulwf": Spec("f", 0x0200),
    "bcf": Spec("fb", 0x9000), "bsf": Spec("fb", 0x8000),
    "btfsc": Spec("fb", 0xB000, skips=True), "btfss": Spec("fb", 0xA000, skips=True),
    "addlw": Spec("k8", 0x0F00), "andlw": Spec("k8", 0x0B00), "iorlw": Spec("k8", 0x0900),
    "movlw": Spec("k8", 0x0E00), "sublw": Spec("k8", 0x0800), "xorlw": Spec("k8", 0x0A00),
    "movlb": Spec("k4", 0x0100),
    "bra": Spec("n11", 0xD000, 2), "rcall": Spec("n11", 0xD800, 2),
    # the conditional branches: 1 cycle, 2 when taken
    "bz": Spec("n8", 0xE000), "bnz": Spec("n8", 0xE100), "bc": Spec("n8", 0xE200), "bnc": Spec("n8", 0xE300),
    "bov": Spec("n8", 0xE400), "bnov": Spec("n8", 0xE500), "bn": Spec("n8", 0xE600), "bnn": Spec("n8", 0xE700),
    "goto": Spec("k20", 0xEF00, 2), "call": Spec("k20", 0xEC00, 2),
    "movff": Spec("ff", 0xC000, 2),
    "nop": Spec("", 0x0000), "clrwdt": Spec("", 0x0004), "sleep": Spec("", 0x0003),
    "return": Spec("", 0x0012, 2), "tblrd*": Spec("", 0x0008, 2),
}


def name(op: str) -> str:
    """The PIC18 mnemonic of a pattern's mnemonic."""
    return ALIASES.get(op, op)


def encode(op: str, *args: int) -> tuple[int, ...]:
    """The instruction's words."""
    spec = INSTRUCTIONS[name(op)]
    return ENCODERS[spec.pattern](spec.opcode, *args)


def words(op: str) -> int:
    return INSTRUCTIONS[name(op)].words
