"""The enhanced mid-range core's banks and core registers, as the shared
emitter (compiler/pic16/emit.py) needs them: BSR holds one of 32 banks of
128 addresses, set by MOVLB; the core registers (INDF0/1, PCL, STATUS,
FSR0/1, BSR, WREG, PCLATH, INTCON at 0x00-0x0B) and the 16 bytes of common
RAM (0x70-0x7F) are in every bank. FSR0 addresses the traditional data
memory with the same 12-bit addresses the instructions' bank and offset
make (FSR0H the high byte), INDF0 what it points at."""

from __future__ import annotations

from ..part import Part

CORE_REGISTERS = 0x0C  # 0x00-0x0B of every bank


class EnhancedCore:
    unknown = (None,)
    moves_far = False
    carry_ops = True

    def __init__(self, part: Part):
        self.status = part.reg("STATUS")
        self.fsr = part.reg("FSR0L")
        self.indf = part.reg("INDF0")
        self._pointer_high = part.reg("FSR0H")
        self._bsr = part.reg("BSR")
        self._common = frozenset(part.common or ())

    def unbanked(self, address: int) -> bool:
        return (address & 0x7F) < CORE_REGISTERS or address in self._common

    def wanted(self, address: int) -> tuple:
        return (address >> 7,)

    def selection(self, component: int, value: int) -> tuple:
        return "movlb", (value,)

    def effect(self, op: str, args: tuple) -> dict[int, int | None]:
        if op == "movlb":
            return {0: args[0]}
        # the emitter asks only of instructions that write their file register
        return {0: None} if args and args[0] & 0x7F == self._bsr else {}

    def home(self, bank: int) -> int:
        return bank << 7 | 0x20

    def pointer_high(self, high: int) -> list[tuple]:
        return [("movlw", (high,)), ("movwf", (self._pointer_high,))]
