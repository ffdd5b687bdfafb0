"""The AVR's program words as the scan-time budget reads them (compiler/budget.py):
each instruction's size, cycles and control flow, decoded from the words alone
(independent of the assembler, so LDmicro's HEX files can be timed too).

Cycles are those of the AVR Instruction Set Manual for the classic cores
(the ATmega8 to ATmega2560): 1 for most; 2 for LD/ST/LDS/STS/PUSH/POP,
MUL, ADIW/SBIW, SBI/CBI, RJMP, IJMP and a branch taken; 3 for LPM and JMP;
RCALL 3, CALL 4, RET/RETI 4, one more each with a 3-byte program counter
(the ATmega2560); a skip 1, or 2 or 3 when it skips a 1- or 2-word
instruction. On parts without JMP (8 KB of flash) RJMP and RCALL wrap
around the flash.

The reduced core (the ATtiny10) encodes a one-word LDS/STS where the classic
cores have LDD/STD: 1 cycle each. Its calls, returns and POP are slower;
`REDUCED` takes the larger of the counts given for the AVRrc column (RCALL
4, RET 6, POP 3), so the bound stays an upper bound.
"""

from __future__ import annotations

from dataclasses import replace

from ..budget import BRANCH, CALL, COMPUTED, JUMP, NEXT, RETURN, SKIP, Instruction

CLOCKS_PER_CYCLE = 1

# (mask, value, mnemonic, cycles) of the one-word instructions that go on to
# the next one; the first that matches decides
_PLAIN = (
    (0xFC00, 0x0C00, "add", 1), (0xFC00, 0x1C00, "adc", 1), (0xFC00, 0x1800, "sub", 1),
    (0xFC00, 0x0800, "sbc", 1), (0xFC00, 0x2000, "and", 1), (0xFC00, 0x2800, "or", 1),
    (0xFC00, 0x2400, "eor", 1), (0xFC00, 0x2C00, "mov", 1), (0xFC00, 0x1400, "cp", 1),
    (0xFC00, 0x0400, "cpc", 1), (0xFF00, 0x0100, "movw", 1), (0xFF00, 0x0200, "muls", 2),
    (0xFF00, 0x0300, "mulsu/fmul", 2), (0xFFFF, 0x0000, "nop", 1), (0xFC00, 0x9C00, "mul", 2),
    (0xF000, 0x3000, "cpi", 1), (0xF000, 0x4000, "sbci", 1), (0xF000, 0x5000, "subi", 1),
    (0xF000, 0x6000, "ori", 1), (0xF000, 0x7000, "andi", 1), (0xF000, 0xE000, "ldi", 1),
    (0xD000, 0x8000, "ld/st y/z+q", 2),
    (0xFE0F, 0x9004, "lpm z", 3), (0xFE0F, 0x9005, "lpm z+", 3), (0xFE0F, 0x9006, "elpm z", 3),
    (0xFE0F, 0x9007, "elpm z+", 3), (0xFE0F, 0x900F, "pop", 2), (0xFE0F, 0x920F, "push", 2),
    *((0xFC0F, value, "ld/st", 2) for value in (0x9001, 0x9002, 0x9009, 0x900A, 0x900C, 0x900D, 0x900E)),
    (0xFE0F, 0x9400, "com", 1), (0xFE0F, 0x9401, "neg", 1), (0xFE0F, 0x9402, "swap", 1),
    (0xFE0F, 0x9403, "inc", 1), (0xFE0F, 0x9405, "asr", 1), (0xFE0F, 0x9406, "lsr", 1),
    (0xFE0F, 0x9407, "ror", 1), (0xFE0F, 0x940A, "dec", 1), (0xFF0F, 0x9408, "bset/bclr", 1),
    (0xFFFF, 0x9588, "sleep", 1), (0xFFFF, 0x9598, "break", 1), (0xFFFF, 0x95A8, "wdr", 1),
    (0xFFFF, 0x95C8, "lpm", 3), (0xFFFF, 0x95D8, "elpm", 3),
    (0xFE00, 0x9600, "adiw/sbiw", 2), (0xFD00, 0x9800, "cbi/sbi", 2),
    (0xF000, 0xB000, "in/out", 1), (0xFC08, 0xF800, "bld/bst", 1),
)
_SKIPS = ((0xFC00, 0x1000, "cpse"), (0xFD00, 0x9900, "sbic/sbis"), (0xFC08, 0xFC00, "sbrc/sbrs"))
# the reduced core's cycles where they differ from the classic ones
REDUCED = {"lds/sts": 1, "rcall": 4, "icall": 4, "ret": 6, "pop": 3}


def _two_words(word: int) -> bool:
    """LDS, STS, JMP, CALL."""
    return (word & 0xFC0F) == 0x9000 or (word & 0xFE0C) == 0x940C


def instruction_at(words: list[int], address: int, device) -> Instruction | None:
    """The instruction at a word address, None where no AVR instruction of
    the part's core is encoded."""
    found = _decode(words, address, device)
    if found is not None and device.data["avr"].get("core") == "reduced" and found.text in REDUCED:
        return replace(found, cycles=REDUCED[found.text])
    return found


def _decode(words: list[int], address: int, device) -> Instruction | None:
    if not 0 <= address < len(words):
        return None
    avr = device.data["avr"]
    flash_words, pc_bytes = avr["flash"] // 2, avr["pc_bytes"]
    word = words[address]
    after = address + 1
    if avr.get("core") == "reduced" and (word & 0xF000) == 0xA000:
        return Instruction(address, 1, 2, text="lds/sts")  # one word; its cycles: REDUCED
    if _two_words(word):
        if after >= len(words):
            return None
        far = ((word >> 4 & 0x1F) << 17 | (word & 1) << 16) | words[after]
        if (word & 0xFE0E) == 0x940C:
            return Instruction(address, 2, 3, JUMP, far, text="jmp")
        if (word & 0xFE0E) == 0x940E:
            return Instruction(address, 2, 2 + pc_bytes, CALL, far, text="call")
        return Instruction(address, 2, 2, text="lds/sts")
    if (word & 0xE000) == 0xC000:  # RJMP, RCALL
        offset = (word & 0x0FFF) - (0x1000 if word & 0x0800 else 0)
        target = (after + offset) % flash_words
        if word & 0x1000:
            return Instruction(address, 1, 1 + pc_bytes, CALL, target, text="rcall")
        return Instruction(address, 1, 2, JUMP, target, text="rjmp")
    if (word & 0xF800) == 0xF000:  # BRBS, BRBC
        offset = (word >> 3 & 0x7F) - (0x80 if word & 0x200 else 0)
        return Instruction(address, 1, 1, BRANCH, after + offset, 2, text="brxx")
    if word in (0x9508, 0x9518):
        return Instruction(address, 1, 2 + pc_bytes, RETURN, text="ret")
    if word in (0x9409, 0x9419):
        return Instruction(address, 1, 2, COMPUTED, text="ijmp")
    if word in (0x9509, 0x9519):
        return Instruction(address, 1, 1 + pc_bytes, COMPUTED, text="icall")
    for mask, value, name in _SKIPS:
        if (word & mask) == value:
            skipped = _decode(words, after, device)
            size = skipped.size if skipped is not None else 1
            return Instruction(address, 1, 1, SKIP, after + size, 1 + size, text=name)
    for mask, value, name, cycles in _PLAIN:
        if (word & mask) == value:
            return Instruction(address, 1, cycles, NEXT, text=name)
    return None
