"""How deep the stack of an image grows, read from its words as the scan-time
budget reads them (flow.py): every path from the reset, each call adding its
return address and its callee's own depth, PUSH and POP moving it by a byte.

The ATtiny10 has 32 bytes of RAM: it cannot keep the classic parts' fixed
reserve for the stack, so its image is measured instead.
"""

from __future__ import annotations

from ..budget import BRANCH, CALL, JUMP, NEXT, RETURN, SKIP
from . import flow

DEEPEST = 256  # a depth no image of ours reaches: pushes in a loop


def depth(words: list[int], device) -> int | None:
    """The most bytes the stack holds at once, or None when that has no
    bound (a subroutine that calls itself, code that cannot be followed)."""
    return _Reader(words, device).routine(0, set())


class _Reader:
    def __init__(self, words: list[int], device):
        self.words, self.device = words, device
        self.pc_bytes = device.data["avr"]["pc_bytes"]
        self.done: dict[int, int | None] = {}

    def routine(self, entry: int, active: set[int]) -> int | None:
        """The deepest the stack goes below a routine's return address."""
        if entry in active:
            return None
        if entry not in self.done:
            self.done[entry] = self._walk(entry, active | {entry})
        return self.done[entry]

    def _walk(self, entry: int, active: set[int]) -> int | None:
        deepest, todo, seen = 0, [(entry, 0)], set()
        while todo:
            address, held = todo.pop()
            if (address, held) in seen:
                continue
            seen.add((address, held))
            ins = flow.instruction_at(self.words, address, self.device)
            if ins is None or held > DEEPEST:
                return None
            held += {"push": 1, "pop": -1}.get(ins.text, 0)
            deepest = max(deepest, held)
            target = ins.target
            if ins.flow == CALL and target is not None:
                inner = self.routine(target, active)
                if inner is None:
                    return None
                deepest = max(deepest, held + self.pc_bytes + inner)
                todo.append((ins.next, held))
            elif ins.flow == JUMP and target is not None:
                todo.append((target, held))
            elif ins.flow in (BRANCH, SKIP) and target is not None:
                todo += [(ins.next, held), (target, held)]
            elif ins.flow == NEXT:
                todo.append((ins.next, held))
            elif ins.flow != RETURN:
                return None  # a computed jump, or one whose target the decoder does not know
        return deepest
