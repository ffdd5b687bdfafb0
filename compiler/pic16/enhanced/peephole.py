"""Jumps and shifts made shorter once the whole program is written, before
it is laid out (the emitter writes each pattern on its own and cannot see
what the next one begins with):

* `skip; GOTO L; x; L:` -> `inverse skip; x` where only labels nothing
  jumps to come between (the emitter's `compress_skips` does it without
  them);
* `skip; GOTO A; GOTO B; A:` -> `inverse skip; GOTO B`;
* a GOTO to the label right after it goes; a GOTO to a GOTO goes to the
  latter's target;
* code after a GOTO, RETURN or RETLW that no label leads into goes;
* `BCF STATUS,C; RRF f` -> `LSRF f` and `BCF STATUS,C; RLF f` -> `LSLF f`
  when Z (which LSRF and LSLF write, RRF and RLF do not) is written again
  before anything reads it.

The labels the scan-time budget and the benchmarks read (scan, wait,
waited, rungN) stay."""

from __future__ import annotations

import re
from collections import Counter
from typing import TypeGuard

from ..asm import Address, Comment, Goto, Ins, Item, Label
from ..emit import STATUS, C, Z
from . import isa

_INVERSE = {"btfsc": "btfss", "btfss": "btfsc"}
_SHIFTS = {"rrf": "lsrf", "rlf": "lslf"}
_KEPT = re.compile(r"scan|wait|waited|rung\d+")
# they write Z whatever it was
_WRITE_Z = frozenset(("addwf", "andwf", "comf", "decf", "incf", "iorwf", "movf", "subwf", "xorwf", "clrf", "clrw",
                      "addlw", "andlw", "iorlw", "sublw", "xorlw", "addwfc", "subwfb", "lslf", "lsrf", "asrf"))


def tighten(items: list[Item]) -> None:
    """Apply the rewrites above until none applies: each sweep is one pass
    over the program (a rewrite looks a few items back for the next)."""
    while _thread(items) | _sweep(items):
        pass


def _skip(item: Item | None) -> TypeGuard[Ins]:
    return isinstance(item, Ins) and item.op in isa.SKIPS


def _jump(item: Item | None) -> TypeGuard[Goto]:
    return isinstance(item, Goto) and not item.call


def _thread(items: list[Item]) -> bool:
    """Each GOTO to a GOTO goes to the latter's target (and so on, a cycle of GOTOs left as it is)."""
    landing: dict[str, Item] = {}  # label -> the first item after it that is not a label or comment
    pending: list[str] = []
    for item in items:
        if isinstance(item, Label):
            pending.append(item.name)
        elif not isinstance(item, Comment):
            landing.update(dict.fromkeys(pending, item))
            pending.clear()

    def final(target: str) -> str:
        seen = {target}
        while True:
            there = landing.get(target)
            if not _jump(there) or there.target in seen:
                return target
            target = there.target
            seen.add(target)

    changed = False
    for i, item in enumerate(items):
        if _jump(item) and final(item.target) != item.target:
            items[i] = Goto(final(item.target), False, item.comment)
            changed = True
    return changed


def _sweep(items: list[Item]) -> bool:
    refs = Counter(item.target for item in items if isinstance(item, (Goto, Address)))

    def idle(item: Item) -> bool:
        """A label nothing jumps to (and nothing reads), or a comment."""
        return isinstance(item, Comment) or (isinstance(item, Label) and not refs[item.name]
                                             and not _KEPT.fullmatch(item.name))

    def next_real(i: int) -> int:
        """The index of the first item from i on that is neither a comment nor an idle label."""
        while i < len(items) and idle(items[i]):
            i += 1
        return i

    def lands(i: int, target: str) -> bool:
        """Items from i on up to `target`'s label are labels and comments only."""
        while i < len(items) and isinstance(items[i], (Label, Comment)):
            item = items[i]
            if isinstance(item, Label) and item.name == target:
                return True
            i += 1
        return False

    def previous(i: int) -> Item | None:
        i -= 1
        while i >= 0 and isinstance(items[i], Comment):
            i -= 1
        return items[i] if i >= 0 else None

    def remove(start: int, stop: int) -> None:
        for gone in items[start:stop]:
            if isinstance(gone, (Goto, Address)):
                refs[gone.target] -= 1
        del items[start:stop]

    def rewrite(i: int) -> bool:
        item = items[i]
        guarded = _skip(previous(i))
        if isinstance(item, Ins) and item.op in _INVERSE and not guarded:
            j = next_real(i + 1)
            jump = items[j] if j < len(items) else None
            if _jump(jump):
                k = next_real(j + 1)
                body = items[k] if k < len(items) else None
                if ((isinstance(body, Ins) and body.op not in isa.SKIPS) or _jump(body)) and lands(k + 1, jump.target):
                    # the GOTO and the idle labels between it and the body go
                    remove(i + 1, k)
                    items[i] = Ins(_INVERSE[item.op], item.args, item.comment)
                    return True
        if _jump(item) and not guarded and lands(i + 1, item.target):
            remove(i, i + 1)
            return True
        if (isinstance(item, Ins) and item.op in isa.ENDS or _jump(item)) and not guarded:
            j = i + 1
            while j < len(items) and (isinstance(items[j], (Ins, Goto, Address)) or idle(items[j])):
                j += 1
            if any(isinstance(it, (Ins, Goto, Address)) for it in items[i + 1:j]):
                remove(i + 1, j)
                return True
        if isinstance(item, Ins) and item.op == "bcf" and item.args == (STATUS, C) and not guarded and i + 1 < len(items):
            shift = items[i + 1]
            if isinstance(shift, Ins) and shift.op in _SHIFTS and _z_dead(items, i + 2):
                items[i:i + 2] = [Ins(_SHIFTS[shift.op], shift.args, shift.comment)]
                return True
        return False

    changed, i = False, 0
    while i < len(items):
        if rewrite(i):
            changed = True
            i = max(0, i - 3)  # a rewrite may complete a pattern that starts a few items back
        else:
            i += 1
    return changed


def _z_dead(items: list[Item], i: int) -> bool:
    """Z is written before it is read, on the straight line from i on (a
    label, jump or skipped write ends the search: Z may be read)."""
    guarded = False
    for item in items[i:]:
        if isinstance(item, Comment):
            continue
        if not isinstance(item, Ins):
            return False
        touches_status = bool(item.args) and item.args[0] == STATUS
        if item.op in ("btfsc", "btfss") and touches_status and item.args[1] == Z:
            return False
        if item.op in _WRITE_Z and not guarded:
            return not touches_status or item.op == "clrf"
        if touches_status and not (item.op in ("bcf", "bsf") and item.args[1] != Z):
            return False
        if item.op in isa.ENDS:
            return False
        guarded = item.op in isa.SKIPS
    return False
