"""The baseline (12-bit) program words as the scan-time budget reads them
(compiler/budget.py): each instruction's cycles and control flow, decoded
from the words alone (independent of the assembler, so LDmicro's HEX files
can be timed too).

Cycles are instruction cycles (4 clocks): 1, or 2 for GOTO, CALL, RETLW and
the instructions that write PCL; a skip (BTFSC, BTFSS, DECFSZ, INCFSZ) takes
2 when it skips. GOTO carries 9 bits of the target, CALL 8 (bit 8 of the PC
cleared): one page of 512 words holds all of a PIC10F20x's memory. SLEEP
jumps to itself: the wake-up is a reset, nothing after it runs. A write
to PCL is a table lookup: it may go to any RETLW of the run that follows it.
"""

from __future__ import annotations

from ..budget import CALL, COMPUTED, JUMP, NEXT, RETURN, SKIP, Instruction

CLOCKS_PER_CYCLE = 4
PCL = 0x02
SLEEP = 0x003


def _is_skip(word: int) -> bool:
    """BTFSC, BTFSS, DECFSZ, INCFSZ."""
    return word >> 9 == 0b011 or word >> 6 in (0b001011, 0b001111)


def _writes_pcl(word: int) -> bool:
    """MOVWF, CLRF or a byte operation (d = 1) into PCL, BCF/BSF PCL."""
    if word & 0x1F != PCL:
        return False
    return (word >> 10 == 0 and word >= 0x040 and bool(word & 0x20)) or word >> 9 == 0b010 or word == 0x022


def _known(word: int) -> bool:
    if word >= 0x400:
        return True  # bit, literal and jump instructions
    if word >= 0x060 or 0x020 <= word <= 0x040:
        return True  # CLRF, byte operations; MOVWF, CLRW
    return word in (0x000, 0x002, 0x003, 0x004, 0x005, 0x006, 0x007)  # NOP, OPTION, SLEEP, CLRWDT, TRIS


def _table(words: list[int], address: int) -> tuple[int, ...]:
    """The RETLW run a write to PCL at `address` jumps into."""
    at = address + 1
    while at < len(words) and words[at] >> 8 == 0x8:
        at += 1
    return tuple(range(address + 1, at))


def instruction_at(words: list[int], address: int, device) -> Instruction | None:
    """The instruction at a word address, None where no baseline instruction is encoded."""
    if not 0 <= address < len(words):
        return None
    word = words[address]
    if word >> 8 == 0x8:
        return Instruction(address, 1, 2, RETURN, text="retlw")
    if word >> 9 == 0b101:
        return Instruction(address, 1, 2, JUMP, word & 0x1FF, text="goto")
    if word >> 8 == 0x9:
        return Instruction(address, 1, 2, CALL, word & 0xFF, text="call")
    if _is_skip(word):
        return Instruction(address, 1, 1, SKIP, address + 2, 2, text="skip")
    if word == SLEEP:  # the part stays here: its wake-up is a reset
        return Instruction(address, 1, 1, JUMP, address, text="sleep")
    if _writes_pcl(word):
        return Instruction(address, 1, 2, COMPUTED, targets=_table(words, address), text="write to PCL")
    return Instruction(address, 1, 1, NEXT) if _known(word) else None
