"""The enhanced mid-range core's banks and core registers, as the shared
emitter (compiler/pic16/emit.py) needs them: BSR holds one of 32 banks of
128 addresses, set by MOVLB; the core registers (INDF0/1, PCL, STATUS,
FSR0/1, BSR, WREG, PCLATH, INTCON at 0x00-0x0B) and the 16 bytes of common
RAM (0x70-0x7F) are in every bank, and so is the latch FSR1 points at
(`Alias`: the assembler names it INDF1). FSR0 addresses the traditional
data memory with the same 12-bit addresses the instructions' bank and
offset make (FSR0H the high byte), INDF0 what it points at."""

from __future__ import annotations

from ..bsr import BsrCore
from ..part import Part
from .latch import Alias

CORE_REGISTERS = 0x0C  # 0x00-0x0B of every bank


class EnhancedCore(BsrCore):
    moves_far = False
    carry_ops = True
    bank_bits, ram_start = 7, 0x20

    def __init__(self, part: Part, alias: Alias | None = None):
        super().__init__(part)
        self._common = frozenset(part.common or ()) | ({alias.latch} if alias is not None else set())

    def unbanked(self, address: int) -> bool:
        return (address & 0x7F) < CORE_REGISTERS or address in self._common

    def writes_bsr(self, op: str, args: tuple) -> bool:
        return bool(args) and args[0] & 0x7F == self._bsr  # BSR is in every bank

    def pointer_high(self, high: int) -> list[tuple]:
        # FSR0H is a core register: CLRF reaches it in one word
        return [("clrf", (self._pointer_high,))] if high == 0 else super().pointer_high(high)
