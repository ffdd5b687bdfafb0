"""The PIC10F20x's core registers for the shared emitter
(compiler/pic16/emit.py): one bank of 32 addresses, which every instruction
reaches, so nothing is ever selected; FSR and INDF as on the mid-range
(FSR's unused high bits read as 1: the back end never compares it)."""

from __future__ import annotations

from ..pic16.emit import FSR, INDF, STATUS


class BaselineCore:
    status, fsr, indf = STATUS, FSR, INDF
    unknown: tuple = ()
    moves_far = False
    carry_ops = False

    def unbanked(self, address: int) -> bool:
        return True

    def wanted(self, address: int) -> tuple:
        return ()

    def selection(self, component: int, value: int) -> tuple:
        raise AssertionError("the baseline has one bank")

    def effect(self, op: str, args: tuple) -> dict[int, int | None]:
        return {}

    def home(self, bank: int) -> int:
        return 0x10

    def pointer_high(self, high: int) -> list[tuple]:
        return []
