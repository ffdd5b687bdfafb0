"""Rewrites of the laid-out items (compiler/pic16/asm.py's) that the shared
patterns cannot see from inside one pattern, each keeping every flag and
register a later instruction reads:

* The labels of the patterns ('_...') and of the intermediate code's
  jumps ('L<n>') that nothing jumps to are dropped, so that
  `compress_skips` (`BTFSC; GOTO L; _ne: BCF; L:` is `BTFSS; BCF`) and
  the next rewrite see through them.
* A signed comparison's fix-up of C followed by a skip on C is a chain
  of two skips (`sign_fixes_folded`).
* W kept: after `MOVF f,W` (f a byte of RAM) and XORLWs, W is f XOR k
  until a label, an unconditional jump, a write of W or a write of f
  (a GOTO a skip passes over keeps it on the way on). A later `MOVF f,W; XORLW
  k2` (an equality test of f against another constant) is `XORLW k^k2`:
  the same W and Z, one word and one cycle less.
"""

from __future__ import annotations

import re

from ..pic16.asm import Address, Comment, Goto, Ins, Label
from ..pic16.emit import INDF, STATUS, C, W
from . import isa

IDLE = re.compile(r"_\w+|L\d+")
FIRST_RAM = 0x08  # below: the core's registers and GPIO, which change on their own (TMR0, the pins)
SKIPS_ON_C = ("btfsc", "btfss")
# (the sign test, the fix-up, the skip on C) that fold into a chain of two skips
FOLDED = {("btfsc", "bcf", "btfss"), ("btfss", "bsf", "btfsc")}


def jump_targets(items: list) -> set[str]:
    """The labels a GOTO or CALL goes to or a MOVLW loads the address of."""
    return {item.target for item in items if isinstance(item, (Goto, Address))}


def without_idle_labels(items: list, kept: set[str]) -> list:
    """The items without the labels of the patterns ('_...') and of the
    intermediate code's jumps ('L<n>') that `kept` does not name."""
    return [item for item in items
            if not (isinstance(item, Label) and IDLE.fullmatch(item.name) and item.name not in kept)]


def _writes_w(ins: Ins) -> bool:
    pattern = isa.INSTRUCTIONS[ins.op].pattern
    return (pattern == "fd" and ins.args[1] == W) or pattern == "k8" or ins.op == "clrw"


def _writes_file(ins: Ins) -> int | None:
    """The file register an instruction writes, None for none."""
    pattern = isa.INSTRUCTIONS[ins.op].pattern
    if pattern == "fd" and ins.args[1] != W or pattern == "f" or ins.op in ("bcf", "bsf"):
        return ins.args[0]
    return None


def _is_skip(item) -> bool:
    return isinstance(item, Ins) and item.op in isa.SKIPS


def w_kept(items: list) -> list:
    """The items with each reload of W that W already holds (up to an XOR
    with a constant) folded into the XORLW after it."""
    out: list = []
    held: tuple[int, int] | None = None  # W == file register ^ constant
    at = 0
    while at < len(items):
        item = items[at]
        at += 1
        guarded = _is_skip(next((x for x in reversed(out) if not isinstance(x, Comment)), None))
        if isinstance(item, Comment) or (isinstance(item, Goto) and guarded):
            out.append(item)  # a GOTO a skip passes over leaves W as it was on the way on
            continue
        if not isinstance(item, Ins):
            held = None
            out.append(item)
            continue
        after = items[at] if at < len(items) else None
        if (not guarded and held is not None and item.op == "movf" and item.args == (held[0], W)
                and isinstance(after, Ins) and after.op == "xorlw"):
            out.append(Ins("xorlw", (held[1] ^ after.args[0],), item.comment))
            held = (held[0], after.args[0])
            at += 1
            continue
        held = _held_after(item, held, guarded)
        out.append(item)
    return out


def _held_after(ins: Ins, held: tuple[int, int] | None, guarded: bool) -> tuple[int, int] | None:
    """What W holds after the instruction (`guarded`: a skip may pass over it)."""
    written = _writes_file(ins)
    if written is not None and held is not None and written in (held[0], INDF):
        held = None
    if ins.op == "movf" and ins.args[1] == W:
        return None if guarded or ins.args[0] < FIRST_RAM else (ins.args[0], 0)
    if ins.op == "xorlw" and held is not None:
        return None if guarded else (held[0], held[1] ^ ins.args[0])
    return None if _writes_w(ins) else held


def _reads(ins: Ins, f: int) -> bool:
    """Whether the instruction reads file register f (INDF reads any)."""
    pattern = isa.INSTRUCTIONS[ins.op].pattern
    return pattern in ("fd", "fb") and ins.args[0] in (f, INDF)


def start_up_trimmed(items: list, scan: str) -> list:
    """The straight-line start-up (from the last label before `scan`; it
    ends in a GOTO or falls into `scan`) without
    a CLRF of a byte it already cleared, nor one of a byte it writes again
    before reading it (a start value stored over the cleared RAM)."""
    end = next(index for index, item in enumerate(items) if isinstance(item, Label) and item.name == scan)
    begin = max((index + 1 for index, item in enumerate(items[:end]) if isinstance(item, Label)), default=0)
    kept: list = []
    zero: set[int] = set()
    for item in items[begin:end]:
        if isinstance(item, Ins) and item.op == "clrf" and item.args[0] in zero:
            continue
        written = _writes_file(item) if isinstance(item, Ins) else None
        if written == INDF:
            zero.clear()
        elif written is not None:
            zero.discard(written)
            if item.op == "clrf":
                zero.add(written)
        kept.append(item)
    trimmed = [item for index, item in enumerate(kept) if not (
        isinstance(item, Ins) and item.op == "clrf" and _overwritten(kept[index + 1:], item.args[0]))]
    return items[:begin] + trimmed + items[end:]


def _overwritten(after: list, f: int) -> bool:
    """Whether f is written by a MOVWF or CLRF in `after` before anything reads it (or a jump leaves)."""
    for item in after:
        if isinstance(item, Goto):
            return False
        if not isinstance(item, Ins):
            continue
        if _reads(item, f):
            return False
        if item.op in ("movwf", "clrf") and item.args[0] == f:
            return True
    return False


def sign_fixes_folded(items: list) -> list:
    """A signed comparison's fix-up of C on the sign bit (asm.py), `BTFSC f,7;
    BCF C` or `BTFSS f,7; BSF C`, followed by the skip on C that runs the next
    instruction when the fix-up did not decide (`BTFSS C` after BCF, `BTFSC C`
    after BSF), is one skip chain: `BTFSC C; BTFSC f,7` (the next instruction
    runs when C is clear or f negative) or `BTFSS C; BTFSS f,7` (C set or f
    positive). One word less; C is left as the subtraction set it, which
    nothing after the comparison's jump reads."""
    out: list = []
    for item in items:
        if (isinstance(item, Ins) and item.op in SKIPS_ON_C and item.args == (STATUS, C) and len(out) >= 2):
            test, fix = out[-2], out[-1]
            if (isinstance(test, Ins) and isinstance(fix, Ins) and test.op in SKIPS_ON_C and test.args[1] == 7
                    and fix.args == (STATUS, C) and (test.op, fix.op, item.op) in FOLDED):
                out[-2:] = [Ins(test.op, (STATUS, C), test.comment), Ins(test.op, test.args)]
                continue
        out.append(item)
    return out
