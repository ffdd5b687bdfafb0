"""The PIC16's program words as the scan-time budget reads them (compiler/budget.py):
each instruction's cycles and control flow, decoded from the words alone
(independent of the assembler, so LDmicro's HEX files can be timed too).

Cycles are instruction cycles (4 clocks): 1, or 2 for GOTO, CALL, RETURN,
RETLW, RETFIE and the instructions that write PCL; a skip (BTFSC, BTFSS,
DECFSZ, INCFSZ) takes 2 when it skips.

GOTO and CALL carry 11 bits of the target; PCLATH<4:3> give its page. The
page is taken from the BCF/BSF PCLATH,3/4 just before the jump (with at most
one skip between: `page selection, skip, GOTO`), else the jump's own page:
how gpasm's PAGESEL, LDmicro and the back end's assembler write far jumps.
A write to PCL is a table lookup: it may go to any RETLW of the run that
follows it (after NOPs and page selections that move the table to a page
boundary).

The enhanced mid-range core (a part whose device file says `"core":
"enhanced"`) adds MOVLB, MOVLP, BRA (2 cycles, a 9-bit signed offset from
the next word), BRW (a table lookup, as a write to PCL: the back end's
tables of up to 256 entries), CALLW (computed: not read), ADDWFC, SUBWFB, LSLF,
LSRF, ASRF, ADDFSR, MOVIW, MOVWI and RESET; its RETLW is 0x34xx only (0x35xx
to 0x37xx are the shifts), and a page is selected by one MOVLP before the
jump.
"""

from __future__ import annotations

from ..budget import CALL, COMPUTED, JUMP, NEXT, RETURN, SKIP, Instruction

CLOCKS_PER_CYCLE = 4
PCL, PCLATH = 0x02, 0x0A
BRW = 0x000B
PAGE_BITS = {3: 0, 4: 1}  # PCLATH bit -> bit of the page number
PAGE_WORDS = 2048


def _is_page_select(word: int, enhanced: bool) -> bool:
    """BCF/BSF PCLATH, 3 or 4; MOVLP on the enhanced core."""
    if enhanced:
        return _is_movlp(word)
    return (word & 0x3800) == 0x1000 and (word & 0x7F) == PCLATH and (word >> 7 & 7) in PAGE_BITS


def _is_movlp(word: int) -> bool:
    return (word & 0x3F80) == 0x3180


def _is_skip(word: int) -> bool:
    """BTFSC, BTFSS, DECFSZ, INCFSZ."""
    return (word & 0x3800) == 0x1800 or (word & 0x3B00) == 0x0B00


def _page(words: list[int], address: int, enhanced: bool) -> int:
    """The page a GOTO or CALL at `address` goes to."""
    page = address // PAGE_WORDS
    at = address - 1
    if at >= 0 and _is_skip(words[at]):
        at -= 1
    if enhanced:
        return (words[at] & 0x7F) >> 3 if at >= 0 and _is_movlp(words[at]) else page
    chosen: dict[int, int] = {}
    while at >= 0 and _is_page_select(words[at], False):
        bit = PAGE_BITS[words[at] >> 7 & 7]
        chosen.setdefault(bit, 1 if words[at] & 0x0400 else 0)
        at -= 1
    for bit, value in chosen.items():
        page = page & ~(1 << bit) | value << bit
    return page


def _table(words: list[int], address: int, enhanced: bool) -> tuple[int, ...]:
    """The RETLW run a write to PCL at `address` jumps into."""
    at = address + 1
    while at < len(words) and (words[at] == 0 or _is_page_select(words[at], enhanced)):
        at += 1
    start = at
    while at < len(words) and _is_retlw(words[at], enhanced):
        at += 1
    return tuple(range(start, at))


def _is_retlw(word: int, enhanced: bool) -> bool:
    return (word & (0x3F00 if enhanced else 0x3C00)) == 0x3400


def _writes_pcl(word: int) -> bool:
    """MOVWF, CLRF or a byte operation (d = 1) into PCL, BCF/BSF PCL."""
    if (word & 0x7F) != PCL:
        return False
    return (word >> 12 == 0 and bool(word & 0x80)) or (word & 0x3800) == 0x1000


def _known(word: int, enhanced: bool) -> bool:
    if enhanced and (word >> 8 in (0x31, 0x35, 0x36, 0x37, 0x3B, 0x3D, 0x3F) or 0x0010 <= word <= 0x003F):
        return True  # MOVLP, ADDFSR, the shifts, SUBWFB, ADDWFC, MOVIW/MOVWI, MOVLB
    if word >> 12 == 3:
        return (word & 0x3F00) != 0x3B00  # the literal operations
    if word >> 12 == 1 or (word >> 12 == 0 and word >= 0x0080):
        return True  # bit operations; MOVWF, CLRW, CLRF, byte operations
    return word in (0x0000, 0x0020, 0x0040, 0x0060, 0x0062, 0x0063, 0x0064, 0x0065, 0x0066, 0x0067)


def instruction_at(words: list[int], address: int, device) -> Instruction | None:
    """The instruction at a word address, None where no mid-range
    instruction is encoded."""
    if not 0 <= address < len(words):
        return None
    word = words[address]
    after = address + 1
    enhanced = device.data[device.family].get("core") == "enhanced"
    if enhanced and (word & 0x3E00) == 0x3200:
        offset = word & 0x1FF
        return Instruction(address, 1, 2, JUMP, after + offset - (0x200 if offset & 0x100 else 0), text="bra")
    if word == 0x0008:
        return Instruction(address, 1, 2, RETURN, text="return")
    if word == 0x0009:
        return Instruction(address, 1, 2, RETURN, text="retfie")
    if _is_retlw(word, enhanced):
        return Instruction(address, 1, 2, RETURN, text="retlw")
    if (word & 0x3000) == 0x2000:
        target = _page(words, address, enhanced) * PAGE_WORDS | (word & 0x7FF)
        if word & 0x0800:
            return Instruction(address, 1, 2, JUMP, target, text="goto")
        return Instruction(address, 1, 2, CALL, target, text="call")
    if _is_skip(word):
        return Instruction(address, 1, 1, SKIP, after + 1, 2, text="skip")
    if _writes_pcl(word) or (enhanced and word == BRW):
        return Instruction(address, 1, 2, COMPUTED, targets=_table(words, address, enhanced), text="write to PCL")
    return Instruction(address, 1, 1, NEXT) if _known(word, enhanced) else None
