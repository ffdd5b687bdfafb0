"""Raw register access (RSFR, WSFR, SSFR, CSFR, TSFR, TCSFR), as LDmicro's
AVR back end compiles it: `sfr` is a data-space address (a number, or a
variable holding one); RSFR copies the byte there into `dest`, WSFR writes
the low byte of `src` there, the others set, clear or test the bits of
`mask` (its low byte). Set and clear read the register, change it and write
it back; the tests read it whether or not power comes in, as a contact reads
its input (docs/semantics.md, Peripherals, "Raw register access")."""

from __future__ import annotations

from .. import ir
from ..errors import OPERAND, fail
from .builder import Builder, Holds, IsSet, lowers
from .io import byte_of

ADDRESSES = 0x10000  # LDmicro loads the address into X: 16 bits


def _address(b: Builder) -> ir.Var | ir.Const:
    address = b.operand(b.arg("sfr"))
    if isinstance(address, ir.Const) and not 0 <= address.value < ADDRESSES:
        raise fail(OPERAND, f"register address {address.value} is outside the data space (0 to 0xFFFF)",
                   b.element)
    return address


def _low_byte(b: Builder, field: str) -> ir.Operand:
    return byte_of(b.operand(b.arg(field)), 0)


@lowers("RSFR")
def read_sfr(b: Builder, el, p: ir.Bit) -> None:
    address, dest = _address(b), b.dest()
    with b.if_(IsSet(p)):
        b.emit(ir.ReadSfr(dest, address))


@lowers("WSFR")
def write_sfr(b: Builder, el, p: ir.Bit) -> None:
    address, value = _address(b), _low_byte(b, "src")
    with b.if_(IsSet(p)):
        b.emit(ir.WriteSfr(address, value))


@lowers("SSFR", "CSFR")
def change_sfr(b: Builder, el, p: ir.Bit) -> None:
    address, mask = _address(b), _low_byte(b, "mask")
    cell = b.temp_var(1)
    with b.if_(IsSet(p)):
        b.emit(ir.ReadSfr(cell, address))
        if el.kind == "SSFR":
            b.emit(ir.Arith("or", cell, cell, mask))
        elif isinstance(mask, ir.Const):
            b.emit(ir.Arith("and", cell, cell, ir.Const(~mask.value & 0xFF)))
        else:  # (x | m) ^ m clears the bits of m
            b.emit(ir.Arith("or", cell, cell, mask))
            b.emit(ir.Arith("xor", cell, cell, mask))
        b.emit(ir.WriteSfr(address, cell))


@lowers("TSFR", "TCSFR")
def test_sfr(b: Builder, el, p: ir.Bit) -> None:
    """TSFR passes power when every bit of the mask is set, TCSFR when every
    one is clear."""
    address, mask = _address(b), _low_byte(b, "mask")
    cell = b.temp_var(1)
    b.emit(ir.ReadSfr(cell, address))
    b.emit(ir.Arith("and", cell, cell, mask))
    with b.if_(Holds(ir.Byte(cell, 0), "!=", mask if el.kind == "TSFR" else ir.Const(0))):
        b.emit(ir.SetBit(p, False))
