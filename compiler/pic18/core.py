"""The PIC18's banks and core registers, as the shared emitter
(compiler/pic16/emit.py) needs them: BSR picks one of sixteen banks of 256
addresses with MOVLB; the access bank (RAM 0x000-0x07F and the SFRs from
0xF80 up) is reached without it; FSR0H:FSR0L is the indirect pointer, INDF0
what it points at."""

from __future__ import annotations

from ..pic16.bsr import BsrCore
from .part import Part


class Pic18Core(BsrCore):
    moves_far = True
    carry_ops = False  # the PIC18 has ADDWFC and SUBWFB, but no LSLF, LSRF, ASRF
    bank_bits, ram_start = 8, 0x80

    def __init__(self, part: Part):
        super().__init__(part)
        self._access = part.common
        self._sfr = part.access_sfr

    def unbanked(self, address: int) -> bool:
        return address in self._access or address >= self._sfr

    def writes_bsr(self, op: str, args: tuple) -> bool:
        # MOVFF writes its second operand (a `#BSR` variable)
        written = args[1] if op == "movff" else args[0] if args else None
        return written == self._bsr
