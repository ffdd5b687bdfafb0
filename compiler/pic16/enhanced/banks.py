"""MOVLBs that select the bank already selected on every way in, found
over the whole program once it is written: the emitter knows nothing at a
loop head or after a CALL (it writes forward), so it selects again at the
top of a wait loop and after every CALL. Here BSR is followed through the
jumps, skips and loops to a fixed point, a CALL keeps it when the routine
called never writes it, and each MOVLB of a bank already known goes.

A computed jump (a write to PCL, a BRW) lands only on a RETLW table in the
programs the patterns write; with any other, or an instruction whose
target is not a label (BRA, CALLW), nothing is removed."""

from __future__ import annotations

from ..asm import Comment, Goto, Ins, Item, Label, Table
from . import isa

PCL, BSR = 0x02, 0x08
UNKNOWN = -1
_READS = frozenset(("btfsc", "btfss"))
_OPAQUE = frozenset(("bra", "callw"))


def drop_known_selections(items: list[Item]) -> bool:
    """Remove the MOVLBs of a bank already selected; True when one went."""
    graph = _Graph.of(items)
    if graph is None:
        return False
    state = graph.solve()
    dead = {i for i in graph.real if _selects(items[i], state.get(i)) and not graph.guarded(i)}
    if not dead:
        return False
    items[:] = [item for i, item in enumerate(items) if i not in dead]
    return True


def _selects(item: Item, bank: int | None) -> bool:
    """The item is a MOVLB of the bank."""
    return isinstance(item, Ins) and item.op == "movlb" and item.args[0] == bank


def _calls(item: Item) -> str | None:
    """The label a CALL goes to."""
    return item.target if isinstance(item, Goto) and item.call else None


def _writes(ins: Ins, register: int) -> bool:
    """The instruction may write the file register (the first operand, by its low 7 bits)."""
    if not ins.args or isa.INSTRUCTIONS[ins.op].pattern not in isa.FILE_PATTERNS or ins.op in _READS:
        return False
    if isa.INSTRUCTIONS[ins.op].pattern == "fd" and ins.args[1] == 0:
        return False  # the result goes to W
    return ins.args[0] & 0x7F == register


class _Graph:
    def __init__(self, items: list[Item], real: list[int], labels: dict[str, int]):
        self.items, self.real, self.labels = items, real, labels
        self._next = {a: b for a, b in zip(real, real[1:])}
        self._prev = {b: a for a, b in zip(real, real[1:])}

    @classmethod
    def of(cls, items: list[Item]) -> _Graph | None:
        real: list[int] = []
        labels: dict[str, int] = {}
        pending: list[str] = []
        for i, item in enumerate(items):
            if isinstance(item, Label):
                pending.append(item.name)
            elif isinstance(item, Table):
                pending.clear()
            elif not isinstance(item, Comment):
                real.append(i)
                labels.update(dict.fromkeys(pending, i))
                pending.clear()
        graph = cls(items, real, labels)
        for i in real:
            item = items[i]
            if isinstance(item, Ins) and (item.op in _OPAQUE or (
                    (item.op == "brw" or _writes(item, PCL)) and not graph._table_follows(i))):
                return None
        return graph

    def _table_follows(self, i: int) -> bool:
        for item in self.items[i + 1:]:
            if isinstance(item, Table):
                return True
            if not isinstance(item, (Label, Comment)):
                return False
        return False

    def guarded(self, i: int) -> bool:
        before = self.items[self._prev[i]] if i in self._prev else None
        return isinstance(before, Ins) and before.op in isa.SKIPS

    def _successors(self, i: int) -> list[int]:
        item = self.items[i]
        after = self._next.get(i)
        if isinstance(item, Goto) and not item.call:
            return [self.labels[item.target]]
        if not isinstance(item, Ins):  # a CALL returns, MOVLW of an address goes on
            return [after] if after is not None else []
        if item.op in isa.ENDS or _writes(item, PCL):
            return []
        found = [after] if after is not None else []
        if item.op in isa.SKIPS and after is not None and self._next.get(after) is not None:
            found.append(self._next[after])
        return found

    def _routine_keeps_bsr(self, label: str, seen: set[str]) -> bool:
        """The routine at the label (and those it calls) writes BSR nowhere."""
        seen.add(label)
        pending, visited = [self.labels[label]], set()
        while pending:
            i = pending.pop()
            if i in visited:
                continue
            visited.add(i)
            item = self.items[i]
            if isinstance(item, Ins) and (item.op == "movlb" or _writes(item, BSR)):
                return False
            if isinstance(item, Goto) and item.call and item.target not in seen and not self._routine_keeps_bsr(
                    item.target, seen):
                return False
            pending += self._successors(i)
        return True

    def solve(self) -> dict[int, int]:
        """The bank selected before each instruction (UNKNOWN when the ways in differ)."""
        callees = {label for label in map(_calls, (self.items[i] for i in self.real)) if label is not None}
        keeps = {label: self._routine_keeps_bsr(label, set()) for label in callees}
        state: dict[int, int] = {}
        pending: list[tuple[int, int]] = [(self.real[0], UNKNOWN)] if self.real else []
        pending += [(self.labels[label], UNKNOWN) for label in callees]
        while pending:
            i, value = pending.pop()
            have = state.get(i)
            merged = value if have is None else (have if have == value else UNKNOWN)
            if merged == have:
                continue
            state[i] = merged
            item = self.items[i]
            out = merged
            if isinstance(item, Ins):
                if item.op == "movlb":
                    out = item.args[0]
                elif _writes(item, BSR):
                    out = UNKNOWN
            elif isinstance(item, Goto) and item.call and not keeps[item.target]:
                out = UNKNOWN
            pending += [(j, out) for j in self._successors(i)]
        return state
