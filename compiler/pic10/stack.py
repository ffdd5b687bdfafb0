"""The return addresses a baseline program needs at once, read from its
words with the budget's decoder (flow.py): the deepest chain of calls from
the reset. The PIC10F20x's hardware stack holds two; a third call
overwrites the oldest and the program returns to the wrong place, so a
deeper chain is refused (GOSUB inside GOSUB, a division inside a GOSUB:
the signed division calls the unsigned one)."""

from __future__ import annotations

from ..budget import CALL, COMPUTED, JUMP, RETURN, SKIP
from . import flow


def _callees(words: list[int], entry: int) -> list[int]:
    """The call targets of the code reached from `entry` without calling."""
    seen: set[int] = set()
    todo, found = [entry], list[int]()
    while todo:
        address = todo.pop()
        if address in seen:
            continue
        seen.add(address)
        ins = flow.instruction_at(words, address, None)
        if ins is None or ins.flow == RETURN:
            continue
        if ins.flow == COMPUTED:
            todo.extend(ins.targets)
            continue
        if ins.flow in (JUMP, CALL, SKIP):
            target = ins.target
            assert target is not None  # the decoder gives a GOTO, a CALL and a skip their target
            if ins.flow == JUMP:
                todo.append(target)
                continue
            if ins.flow == CALL and target not in found:
                found.append(target)
            if ins.flow == SKIP:
                todo.append(target)
        todo.append(ins.next)
    return found


def deepest(words: list[int], entry: int = 0) -> list[int]:
    """The longest chain of calls from `entry`: the call targets, outermost first."""
    chains: dict[int, list[int]] = {}

    def chain(address: int, active: frozenset[int]) -> list[int]:
        if address in active:  # a call of itself: deeper than any stack
            return [address] * 3
        if address not in chains:
            longest: list[int] = []
            for callee in _callees(words, address):
                below = [callee, *chain(callee, active | {address})]
                if len(below) > len(longest):
                    longest = below
            chains[address] = longest
        return chains[address]

    return chain(entry, frozenset())
