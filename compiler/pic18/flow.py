"""The PIC18's program words as the scan-time budget reads them
(compiler/budget.py): each instruction's size, cycles and control flow,
decoded from the words alone (independent of the assembler).

Cycles are instruction cycles (4 clocks): 1, or 2 for BRA, RCALL, GOTO,
CALL, RETURN, RETLW, RETFIE, the conditional branches when taken, MOVFF,
LFSR and TBLRD; a skip (BTFSC, BTFSS, DECFSZ, INCFSZ, DCFSNZ, INFSNZ,
CPFSxx, TSTFSZ) takes 2 when it skips a one-word instruction and 3 over a
two-word one. GOTO, CALL, MOVFF and LFSR take two words; their second word
(1111 xxxx...) is a NOP when reached alone.
"""

from __future__ import annotations

from ..budget import BRANCH, CALL, JUMP, NEXT, RETURN, SKIP, Instruction

CLOCKS_PER_CYCLE = 4


def _signed(value: int, bits: int) -> int:
    return value - (1 << bits) if value >> (bits - 1) & 1 else value


def _size(word: int) -> int:
    """Words the instruction starting with this word takes."""
    top = word >> 8
    return 2 if word >> 12 == 0xC or top in (0xEC, 0xED, 0xEE, 0xEF) else 1


def _is_skip(word: int) -> bool:
    """BTFSC, BTFSS; DECFSZ, INCFSZ, DCFSNZ, INFSNZ; CPFSLT, CPFSEQ, CPFSGT, TSTFSZ."""
    return (word >> 13 == 0b101 or (word >> 10) in (0b001011, 0b001111, 0b010011, 0b010010)
            or (word >> 9) in (0b0110000, 0b0110001, 0b0110010, 0b0110011))


def _known(word: int) -> bool:
    top4 = word >> 12
    if top4 in (0x1, 0x2, 0x3, 0x4, 0x5, 0x6, 0x7, 0x8, 0x9, 0xA, 0xB, 0xC):
        return True  # byte and bit operations on files, MOVFF
    if top4 == 0x0:
        if word >= 0x0100:
            return True  # MOVLB, MULWF, DECF, the literal operations
        return word in (0x0000, 0x0003, 0x0004, 0x0006, 0x0007, 0x0008, 0x0009, 0x000A, 0x000B, 0x000C, 0x000D,
                        0x000E, 0x000F, 0x0010, 0x0011, 0x0012, 0x0013, 0x00FF)
    if top4 == 0xE:
        return not 0xE8 <= word >> 8 <= 0xEB  # branches, CALL, LFSR, GOTO (not the extended set's)
    return top4 == 0xD or top4 == 0xF  # BRA, RCALL; a second word alone is a NOP


def instruction_at(words: list[int], address: int, device) -> Instruction | None:
    """The instruction at a word address, None where no PIC18 instruction is encoded."""
    if not 0 <= address < len(words):
        return None
    word = words[address]
    size = _size(word)
    if address + size > len(words) or not _known(word):
        return None
    after = address + size
    if word in (0x0012, 0x0013):
        return Instruction(address, 1, 2, RETURN, text="return")
    if word in (0x0010, 0x0011):
        return Instruction(address, 1, 2, RETURN, text="retfie")
    if word >> 8 == 0x0C:
        return Instruction(address, 1, 2, RETURN, text="retlw")
    if word >> 11 == 0b11010:
        return Instruction(address, 1, 2, JUMP, after + _signed(word & 0x7FF, 11), text="bra")
    if word >> 11 == 0b11011:
        return Instruction(address, 1, 2, CALL, after + _signed(word & 0x7FF, 11), text="rcall")
    if word >> 11 == 0b11100:  # BZ, BNZ, BC, BNC, BOV, BNOV, BN, BNN
        return Instruction(address, 1, 1, BRANCH, after + _signed(word & 0xFF, 8), 2, text="branch")
    if word >> 8 in (0xEF, 0xEC, 0xED):
        target = (words[address + 1] & 0xFFF) << 8 | word & 0xFF
        if word >> 8 == 0xEF:
            return Instruction(address, 2, 2, JUMP, target, text="goto")
        return Instruction(address, 2, 2, CALL, target, text="call")
    if _is_skip(word):
        skipped = _size(words[after]) if after < len(words) else 1
        return Instruction(address, 1, 1, SKIP, after + skipped, 1 + skipped, text="skip")
    cycles = 2 if size == 2 or word in (0x0008, 0x0009, 0x000A, 0x000B, 0x000C, 0x000D, 0x000E, 0x000F) else 1
    return Instruction(address, size, cycles, NEXT)
