"""The AVR instruction set as a table: each mnemonic with its operand pattern
and opcode, and one encoder per operand pattern. Only what the back end emits
is listed; the listing writes the same mnemonics, so GNU avr-as reassembles
it to the same words (tests/test_compiler_encoding.py checks this).

Operands are plain integers: registers 0..31, I/O addresses 0..63 (for IN,
OUT, SBI...), data-space addresses for LDS/STS, and for jumps and branches
the word offset (relative) or word address (JMP/CALL) the assembler computed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


class EncodingError(ValueError):
    """An operand out of its instruction's range (a back-end bug or a
    program too big for a short jump: the assembler relaxes those first)."""


def _check(value: int, low: int, high: int, what: str) -> int:
    if not low <= value <= high:
        raise EncodingError(f"{what} {value} out of range {low}..{high}")
    return value


def _reg(r: int) -> int:
    return _check(r, 0, 31, "register")


def _upper(r: int) -> int:
    return _check(r, 16, 31, "register (r16..r31)") - 16


# --- operand patterns ----------------------------------------------------------
# each takes the base opcode and the operands, returns the instruction's words

def _none(base, *_):
    return [base]


def _rd(base, d):
    return [base | _reg(d) << 4]


def _rd_rr(base, d, r):
    _reg(d), _reg(r)
    return [base | (r & 0x10) << 5 | d << 4 | (r & 0x0F)]


def _rd_same(base, d):
    """The one-register aliases: LSL r = ADD r,r; ROL r = ADC r,r..."""
    return _rd_rr(base, d, d)


def _rd_k8(base, d, k):
    k = _check(k, -128, 255, "constant") & 0xFF
    return [base | (k & 0xF0) << 4 | _upper(d) << 4 | (k & 0x0F)]


def _rd_bit(base, d, b):
    return [base | _reg(d) << 4 | _check(b, 0, 7, "bit")]


def _io_bit(base, a, b):
    return [base | _check(a, 0, 31, "I/O address") << 3 | _check(b, 0, 7, "bit")]


def _rd_io(base, d, a):
    _check(a, 0, 63, "I/O address")
    return [base | (a & 0x30) << 5 | _reg(d) << 4 | (a & 0x0F)]


def _io_rr(base, a, r):
    return _rd_io(base, r, a)


def _branch(base, k):
    return [base | (_check(k, -64, 63, "branch offset") & 0x7F) << 3]


def _rel12(base, k):
    return [base | (_check(k, -2048, 2047, "relative jump") & 0x0FFF)]


def _abs22(base, k):
    _check(k, 0, (1 << 22) - 1, "jump address")
    return [base | (k >> 17) << 4 | (k >> 16 & 1), k & 0xFFFF]


def _rd_addr16(base, d, k):
    return [base | _reg(d) << 4, _check(k, 0, 0xFFFF, "data address")]


def _addr16_rr(base, k, r):
    return _rd_addr16(base, r, k)


def _rd_addr7(base, d, k):
    """The reduced core's one-word LDS/STS: data addresses 0x40..0xBF, bit 7
    the inverse of bit 6."""
    _check(k, 0x40, 0xBF, "data address (0x40..0xBF)")
    return [base | (k & 0x40) << 2 | (k & 0x30) << 5 | _upper(d) << 4 | (k & 0x0F)]


def _addr7_rr(base, k, r):
    return _rd_addr7(base, r, k)


def _pair_k6(base, d, k):
    if d not in (24, 26, 28, 30):
        raise EncodingError(f"SBIW needs r24, r26, r28 or r30, not r{d}")
    _check(k, 0, 63, "constant")
    return [base | (k & 0x30) << 2 | (d - 24) // 2 << 4 | (k & 0x0F)]


def _movw(base, d, r):
    if d % 2 or r % 2:
        raise EncodingError("MOVW needs even registers")
    return [base | _reg(d) // 2 << 4 | _reg(r) // 2]


@dataclass(frozen=True)
class Opcode:
    base: int
    encode: Callable
    syntax: str  # how the listing writes the operands: "d,r", "d,K", "A,b" ...

    @property
    def words(self) -> int:
        return 2 if self.encode in (_abs22, _rd_addr16, _addr16_rr) else 1


def _ops(pattern: Callable, syntax: str, **bases: int) -> dict[str, Opcode]:
    return {name: Opcode(base, pattern, syntax) for name, base in bases.items()}


# mnemonic -> opcode; pointer forms of LD/ST are spelled as their own
# mnemonics ("ld_x+" is `ld Rd, X+`) so that every entry has one pattern
OPCODES: dict[str, Opcode] = {
    **_ops(_none, "", nop=0x0000, ret=0x9508, cli=0x94F8, set=0x9468, clt=0x94E8, sleep=0x9588,
           wdr=0x95A8),
    **_ops(_rd, "d", com=0x9400, neg=0x9401, swap=0x9402, inc=0x9403, asr=0x9405, lsr=0x9406,
           ror=0x9407, dec=0x940A, push=0x920F, pop=0x900F),
    **_ops(_rd_rr, "d,r", add=0x0C00, adc=0x1C00, sub=0x1800, sbc=0x0800, and_=0x2000, or_=0x2800,
           eor=0x2400, mov=0x2C00, cp=0x1400, cpc=0x0400, mul=0x9C00),
    **_ops(_rd_same, "d", lsl=0x0C00, rol=0x1C00, tst=0x2000, clr=0x2400),
    **_ops(_rd_k8, "d,K", ldi=0xE000, cpi=0x3000, subi=0x5000, sbci=0x4000, ori=0x6000, andi=0x7000),
    **_ops(_rd_bit, "d,b", sbrc=0xFC00, sbrs=0xFE00, bst=0xFA00, bld=0xF800),
    **_ops(_io_bit, "A,b", cbi=0x9800, sbi=0x9A00, sbic=0x9900, sbis=0x9B00),
    **_ops(_rd_io, "d,A", in_=0xB000),
    **_ops(_io_rr, "A,r", out=0xB800),
    **_ops(_branch, "k", breq=0xF001, brne=0xF401, brcs=0xF000, brcc=0xF400, brmi=0xF002,
           brpl=0xF402, brvs=0xF003, brvc=0xF403, brlt=0xF004, brge=0xF404, brts=0xF006,
           brtc=0xF406),
    **_ops(_rel12, "k", rjmp=0xC000, rcall=0xD000),
    **_ops(_abs22, "k", jmp=0x940C, call=0x940E),
    **_ops(_rd_addr16, "d,k", lds=0x9000),
    **_ops(_addr16_rr, "k,r", sts=0x9200),
    **_ops(_pair_k6, "d,K", sbiw=0x9700),
    **_ops(_movw, "d,r", movw=0x0100),
    **_ops(_rd, "d,X", ld_x=0x900C),
    **_ops(_rd, "X,r", st_x=0x920C),
    **_ops(_rd, "X+,r", st_xp=0x920D),
    **_ops(_rd, "d,Z+", lpm_p=0x9005, ld_zp=0x9001),
}


@dataclass(frozen=True)
class Core:
    """An instruction-set variant: the classic AVR core, or the reduced core
    (AVRrc: ATtiny4/5/9/10/20/40) with sixteen registers, no MUL, MOVW,
    ADIW/SBIW, LPM or JMP/CALL, a one-word LDS/STS, and its I/O registers at
    data addresses 0x00..0x3F (registers are not in the data space), flash
    read with LD through the data space at `flash_data`."""

    name: str
    registers: range
    io_offset: int  # data address of I/O address 0
    lacks: frozenset[str]
    forms: dict[str, Opcode]  # the core's own encoding of a mnemonic
    flash_data: int | None  # data address of flash byte 0 (LD reads it), None: LPM reads flash

    def opcode(self, mnemonic: str) -> Opcode:
        if mnemonic in self.lacks:
            raise EncodingError(f"the {self.name} core has no {SPELLING.get(mnemonic, mnemonic).upper()}")
        return self.forms.get(mnemonic) or OPCODES[mnemonic]

    def has(self, mnemonic: str) -> bool:
        return mnemonic not in self.lacks

    @property
    def io_end(self) -> int:
        """First data address IN/OUT cannot reach."""
        return self.io_offset + 0x40

    @property
    def bit_io_end(self) -> int:
        """First data address SBI/CBI/SBIS/SBIC cannot reach."""
        return self.io_offset + 0x20


CLASSIC = Core("classic", range(32), 0x20, frozenset(), {}, None)
REDUCED = Core("reduced", range(16, 32), 0x00,
               frozenset({"mul", "movw", "sbiw", "lpm_p", "jmp", "call"}),
               {"lds": Opcode(0xA000, _rd_addr7, "d,k"), "sts": Opcode(0xA800, _addr7_rr, "k,r")}, 0x4000)
CORES = {core.name: core for core in (CLASSIC, REDUCED)}

# the mnemonic avr-as knows, where the table's key differs from it
SPELLING = {"and_": "and", "or_": "or", "in_": "in", "ld_x": "ld", "st_x": "st", "st_xp": "st", "lpm_p": "lpm",
            "ld_zp": "ld"}

# the branch taken on the opposite condition
INVERSE = {"breq": "brne", "brne": "breq", "brcs": "brcc", "brcc": "brcs", "brmi": "brpl",
           "brpl": "brmi", "brvs": "brvc", "brvc": "brvs", "brlt": "brge", "brge": "brlt",
           "brts": "brtc", "brtc": "brts"}

# skip instructions: the opposite test of the same bit
SKIP_INVERSE = {"sbrc": "sbrs", "sbrs": "sbrc", "sbic": "sbis", "sbis": "sbic"}


def encode(mnemonic: str, *operands: int, core: Core = CLASSIC) -> list[int]:
    op = core.opcode(mnemonic)
    for field, value in zip(op.syntax.split(","), operands):
        if field in ("d", "r") and value not in core.registers:
            raise EncodingError(f"register r{value} is not one of the {core.name} core's")
    return op.encode(op.base, *operands)


def size(mnemonic: str, core: Core = CLASSIC) -> int:
    """Words the instruction takes."""
    return core.opcode(mnemonic).words


def text(mnemonic: str, *operands: int) -> str:
    """The instruction in GNU avr-as syntax (jump operands are written by the
    assembler, which knows their labels)."""
    syntax = OPCODES[mnemonic].syntax
    name = SPELLING.get(mnemonic, mnemonic)
    if not syntax:
        return name
    parts = []
    values = iter(operands)
    for field in syntax.split(","):
        if field in ("d", "r"):
            parts.append(f"r{next(values)}")
        elif field in ("K", "b", "A", "k"):
            value = next(values)
            parts.append(f"0x{value & 0xFF:02x}" if field == "K" else f"0x{value:02x}" if field == "A"
                         else f"0x{value:04x}" if field == "k" else str(value))
        else:
            parts.append(field)  # X, X+, Y+, Z, Z+
    return f"{name} {', '.join(parts)}"
