"""The enhanced mid-range assembler: the mid-range one (compiler/pic16/asm.py)
with its own instruction table, and a page selected by one MOVLP (PCLATH<6:0>
at once) rather than a BCF/BSF per PCLATH bit."""

from __future__ import annotations

from .. import asm as midrange
from . import isa


class Assembler(midrange.Assembler):
    isa = isa
    # program memory is at 0x8000 up for FSR0/FSR1: gpasm's high() of a code label has bit 7 set (PCLATH ignores it)
    code_space = 0x8000

    def _select(self, which: str) -> list[midrange._Word]:
        return [midrange._Word("pagesel", select=which)]

    def _page_selection(self, word: midrange._Word, page: int) -> tuple[str, tuple, str]:
        high = page * self.page_words >> 8
        return "movlp", (high,), f"0x{high:02X}"
