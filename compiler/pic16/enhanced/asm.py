"""The enhanced mid-range assembler: the mid-range one (compiler/pic16/asm.py)
with its own instruction table, and a page selected by one MOVLP (PCLATH<6:0>
at once) rather than a BCF/BSF per PCLATH bit. With an `Alias` the program
begins by pointing FSR1 at a latch, and every instruction on that latch
names INDF1 instead (no bank needed). Before the layout, `tighten` shortens
jumps and shifts (peephole.py) and the MOVLBs of a bank already selected
go (banks.py)."""

from __future__ import annotations

from .. import asm as midrange
from . import isa
from .banks import drop_known_selections
from .latch import Alias
from .peephole import tighten


class Assembler(midrange.Assembler):
    isa = isa
    # program memory is at 0x8000 up for FSR0/FSR1: gpasm's high() of a code label has bit 7 set (PCLATH ignores it)
    code_space = 0x8000
    relative_tables = True

    def __init__(self, flash_words: int, page_words: int, alias: Alias | None = None):
        super().__init__(flash_words, page_words)
        self._alias = alias
        if alias is not None:
            for op, args in alias.prologue():
                super().emit(op, *args, comment="FSR1: the outputs' latch" if op == "movlw" and not self.items else "")

    def emit(self, op: str, *args: int, comment: str = "") -> None:
        alias = self._alias
        if alias is not None and args and args[0] == alias.latch and isa.INSTRUCTIONS[op].pattern in isa.FILE_PATTERNS:
            args = (alias.indf, *args[1:])
            comment = comment or f"0x{alias.latch:03X} through FSR1"
        super().emit(op, *args, comment=comment)

    def assemble(self, processor: str, config: dict[int, int]) -> midrange.Assembled:
        tighten(self.items)
        while drop_known_selections(self.items):
            tighten(self.items)
        return super().assemble(processor, config)

    def _groups(self, far: set[int]) -> list[tuple[list, list[midrange._Word], bool]]:
        """The mid-range's, with a BRW and the RETLW table after it one group:
        nothing (a NOP before a page boundary, a page selection) may come
        between the jump and the entries it counts from."""
        groups: list[tuple[list, list[midrange._Word], bool]] = []
        for before, words, falls in super()._groups(far):
            if groups and groups[-1][1] and groups[-1][1][-1].op == "brw" and words and words[0].op == "retlw":
                jump_before, jump, _ = groups.pop()
                # the entries' label, which nothing reads here, goes: a label can only begin a group
                before, words = jump_before + [item for item in before if not isinstance(item, midrange.Label)], jump + words
            groups.append((before, words, falls))
        return groups

    def _select(self, which: str) -> list[midrange._Word]:
        return [midrange._Word("pagesel", select=which)]

    def _page_selection(self, word: midrange._Word, page: int) -> tuple[str, tuple, str]:
        high = page * self.page_words >> 8
        return "movlp", (high,), f"0x{high:02X}"
