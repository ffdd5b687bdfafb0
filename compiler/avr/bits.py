"""Bit patterns, by where the bit lives.

| bit in            | test (skip next)   | write                  | to/from the T flag      |
|-------------------|--------------------|------------------------|-------------------------|
| r16..r31          | SBRS/SBRC r,b      | ORI/ANDI r,mask        | BST/BLD r,b             |
| r3..r15           | SBRS/SBRC r,b      | SET/CLT + BLD r,b      | BST/BLD r,b             |
| I/O below 0x40    | SBIS/SBIC A,b      | SBI/CBI A,b            | IN, BST / IN, BLD, OUT  |
| other I/O, RAM    | LDS/IN r0, SBRS    | LDS, ORI/ANDI, STS     | LDS, BST / LDS, BLD, STS|

A conditional write is a skip over a jump around the write; the assembler's
peephole (asm.compress_skips) turns a skip over a jump over one instruction
into a single skip.
"""

from __future__ import annotations

from collections.abc import Callable

from .emit import SCRATCH, Emitter
from .memory import MemBit, RegBit

Loc = RegBit | MemBit


def skip_if(e: Emitter, loc: Loc, value: bool) -> None:
    """Skip the next instruction when the bit equals `value`."""
    if isinstance(loc, RegBit):
        e.ins("sbrs" if value else "sbrc", loc.reg, loc.bit)
    elif (io := e.bit_io(loc.addr)) is not None:
        e.ins("sbis" if value else "sbic", io, loc.bit)
    else:
        e.load_byte(loc.addr, e.loaded, loc.ram)
        e.ins("sbrs" if value else "sbrc", e.loaded, loc.bit)


def write(e: Emitter, loc: Loc, value: bool) -> None:
    mask = 1 << loc.bit
    if isinstance(loc, RegBit):
        if loc.reg >= 16:
            e.ins("ori" if value else "andi", loc.reg, mask if value else ~mask & 0xFF)
        else:
            e.ins("set" if value else "clt")
            e.ins("bld", loc.reg, loc.bit)
    elif (io := e.bit_io(loc.addr)) is not None:
        e.ins("sbi" if value else "cbi", io, loc.bit)
    else:
        e.load_byte(loc.addr, SCRATCH, loc.ram)
        e.ins("ori" if value else "andi", SCRATCH, mask if value else ~mask & 0xFF)
        e.store_byte(loc.addr, SCRATCH, loc.ram)


def when(e: Emitter, loc: Loc, value: bool, body: Callable[[], None]) -> None:
    """Run `body` only when the bit equals `value`."""
    skip = e.new_label()
    skip_if(e, loc, value)
    e.jump(skip)
    body()
    e.label(skip)


def jump_if(e: Emitter, loc: Loc, value: bool, target: str) -> None:
    skip_if(e, loc, not value)
    e.jump(target)


def _to_t(e: Emitter, loc: Loc) -> None:
    if isinstance(loc, RegBit):
        e.ins("bst", loc.reg, loc.bit)
    else:
        e.load_byte(loc.addr, e.loaded, loc.ram)
        e.ins("bst", e.loaded, loc.bit)


def from_t(e: Emitter, loc: Loc) -> None:
    """The bit = the T flag."""
    if isinstance(loc, RegBit):
        e.ins("bld", loc.reg, loc.bit)
    else:
        e.load_byte(loc.addr, SCRATCH, loc.ram)
        e.ins("bld", SCRATCH, loc.bit)
        e.store_byte(loc.addr, SCRATCH, loc.ram)


def _toggle(e: Emitter, loc: Loc) -> None:
    mask = e.constant_reg(1 << loc.bit, SCRATCH + 1)
    if isinstance(loc, RegBit):
        e.ins("eor", loc.reg, mask)
    else:
        e.load_byte(loc.addr, SCRATCH, loc.ram)
        e.ins("eor", SCRATCH, mask)
        e.store_byte(loc.addr, SCRATCH, loc.ram)


def copy(e: Emitter, dst: Loc, src: Loc, invert: bool) -> None:
    if dst == src:
        if invert:
            _toggle(e, dst)
        return
    if isinstance(dst, MemBit) and e.bit_io(dst.addr) is not None:
        # a pin: set, then clear, each a skip over one SBI/CBI, so that it
        # never glitches; the source byte is read once
        if isinstance(src, MemBit):
            e.load_byte(src.addr, e.loaded, src.ram)
            src = RegBit(e.loaded, src.bit)
        skip_if(e, src, invert)
        write(e, dst, True)
        skip_if(e, src, not invert)
        write(e, dst, False)
        return
    _to_t(e, src)
    from_t(e, dst)
    if invert:
        _toggle(e, dst)


def and_(e: Emitter, dst: Loc, src: Loc, invert: bool) -> None:
    """dst = dst and (src, or not src when inverted)"""
    when(e, src, invert, lambda: write(e, dst, False))


def or_(e: Emitter, dst: Loc, src: Loc) -> None:
    when(e, src, True, lambda: write(e, dst, True))
