"""The PIC18's banks and core registers, as the shared emitter
(compiler/pic16/emit.py) needs them: BSR picks one of sixteen banks of 256
addresses with MOVLB; the access bank (RAM 0x000-0x07F and the SFRs from
0xF80 up) is reached without it; FSR0H:FSR0L is the indirect pointer, INDF0
what it points at."""

from __future__ import annotations

from .part import Part


class Pic18Core:
    unknown = (None,)
    moves_far = True
    carry_ops = False  # the PIC18 has ADDWFC and SUBWFB, but no LSLF, LSRF, ASRF

    def __init__(self, part: Part):
        self.status = part.reg("STATUS")
        self.fsr = part.reg("FSR0L")
        self.indf = part.reg("INDF0")
        self._pointer_high = part.reg("FSR0H")
        self._bsr = part.reg("BSR")
        self._access = part.common
        self._sfr = part.access_sfr

    def unbanked(self, address: int) -> bool:
        return address in self._access or address >= self._sfr

    def wanted(self, address: int) -> tuple:
        return (address >> 8,)

    def selection(self, component: int, value: int) -> tuple:
        return "movlb", (value,)

    def effect(self, op: str, args: tuple) -> dict[int, int | None]:
        if op == "movlb":
            return {0: args[0]}
        # the emitter asks only of instructions that write their file register (a `#BSR` variable)
        written = args[1] if op == "movff" else args[0] if args else None
        return {0: None} if written == self._bsr else {}

    def home(self, bank: int) -> int:
        return bank << 8 | 0x80

    def pointer_high(self, high: int) -> list[tuple]:
        return [("movlw", (high,)), ("movwf", (self._pointer_high,))]
