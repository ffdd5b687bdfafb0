"""What the cores that bank with BSR share, as the shared emitter
(compiler/pic16/emit.py) needs it: the enhanced mid-range PIC16 (banks of
128 addresses) and the PIC18 (banks of 256). MOVLB selects the bank; a
write to BSR itself leaves it unknown; FSR0H:FSR0L is the indirect pointer,
INDF0 what it points at. A core says how wide its banks are, where a
bank's general-purpose RAM starts and what every bank reaches."""

from __future__ import annotations

from .part import Part


class BsrCore:
    unknown = (None,)
    bank_bits = 8  # log2 of a bank's addresses
    ram_start = 0  # a bank's first general-purpose address, from the bank's start

    def __init__(self, part: Part):
        self.status = part.reg("STATUS")
        self.fsr = part.reg("FSR0L")
        self.indf = part.reg("INDF0")
        self._pointer_high = part.reg("FSR0H")
        self._bsr = part.reg("BSR")

    def wanted(self, address: int) -> tuple:
        return (address >> self.bank_bits,)

    def selection(self, component: int, value: int) -> tuple:
        return "movlb", (value,)

    def effect(self, op: str, args: tuple) -> dict[int, int | None]:
        if op == "movlb":
            return {0: args[0]}
        # the emitter asks only of instructions that write their file register
        return {0: None} if self.writes_bsr(op, args) else {}

    def writes_bsr(self, op: str, args: tuple) -> bool:
        return bool(args) and args[0] == self._bsr

    def home(self, bank: int) -> int:
        return bank << self.bank_bits | self.ram_start

    def pointer_high(self, high: int) -> list[tuple]:
        return [("movlw", (high,)), ("movwf", (self._pointer_high,))]
