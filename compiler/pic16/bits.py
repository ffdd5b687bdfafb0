"""Bit patterns: every bit is a bit of a file register, tested with
BTFSC/BTFSS and written with BCF/BSF.

A conditional write is a skip over a GOTO around the write; the emitter's
`compress_skips` makes it a single skip over the write when the write needs
no bank selection of its own. A copy to a pin sets it when the source is set
and clears it when it is clear, so that it never glitches (a source in
another bank is read into Z first, so that the pin's bank is selected once);
a copy to a RAM bit clears it, then sets it if the source is set (one word
less).
"""

from __future__ import annotations

from collections.abc import Callable

from .emit import Emitter, Z
from .memory import FileBit


def skip_if(e: Emitter, loc: FileBit, value: bool) -> None:
    """Skip the next instruction when the bit equals `value`."""
    e.ins("btfss" if value else "btfsc", loc.addr, loc.bit)


def write(e: Emitter, loc: FileBit, value: bool) -> None:
    e.ins("bsf" if value else "bcf", loc.addr, loc.bit)


def when(e: Emitter, loc: FileBit, value: bool, body: Callable[[], None]) -> None:
    """Run `body` only when the bit equals `value`."""
    skip = e.new_label()
    skip_if(e, loc, value)
    e.goto(skip)
    body()
    e.label(skip)


def jump_if(e: Emitter, loc: FileBit, value: bool, target: str) -> None:
    skip_if(e, loc, not value)
    e.goto(target)


def _near(e: Emitter, dst: FileBit, src: FileBit) -> None:
    """Select the destination's bank first when the source is reached from
    any bank: the skips then test it there and the writes need no selection
    of their own (each skip guards the write alone, no GOTO around it)."""
    if e.reaches(src.addr):
        e.select(dst.addr)


def copy(e: Emitter, dst: FileBit, src: FileBit, invert: bool) -> None:
    if dst == src:
        if invert:
            e.load_constant(1 << dst.bit)
            e.ins("xorwf", dst.addr, 1)
        return
    if dst.ram:
        # RAM may change for an instruction's time: clear, then set if the source says so
        write(e, dst, False)
        when(e, src, not invert, lambda: write(e, dst, True))
        return
    if not (e.reaches(src.addr) or e.reaches(dst.addr)) and e.core.wanted(src.addr) != e.core.wanted(dst.addr):
        # banks apart (an input's PORTx and an output's LATx on the enhanced core): the source bit
        # into Z through W, then the pin's bank once and a skip on Z before each write
        e.load(src.addr)
        e.select(dst.addr)
        e.ins("andlw", 1 << src.bit)
        clear = FileBit(e.status, Z, False)
        when(e, clear, False, lambda: write(e, dst, not invert))
        when(e, clear, True, lambda: write(e, dst, invert))
        return
    _near(e, dst, src)
    when(e, src, not invert, lambda: write(e, dst, True))
    when(e, src, invert, lambda: write(e, dst, False))


def and_(e: Emitter, dst: FileBit, src: FileBit, invert: bool) -> None:
    """dst = dst and (src, or not src when inverted)"""
    _near(e, dst, src)
    when(e, src, invert, lambda: write(e, dst, False))


def or_(e: Emitter, dst: FileBit, src: FileBit) -> None:
    _near(e, dst, src)
    when(e, src, True, lambda: write(e, dst, True))
