"""The scan-time budget: the worst-case cycles of one scan, from the code a
back end wrote.

LDmicro never checks that a scan fits its cycle time: a scan that takes
longer silently stretches every timer. The compiler knows the code it wrote,
so it bounds the longest path from the start of the scan loop (label `scan`)
to the start of its wait (label `wait`), through every call, with every loop
bounded by the `LoopBound` its back end gave the loop's head (`Image.loops`).

The analysis reads a neutral description of program memory: an
`Instruction` per address (size, cycles, control flow), which a `Decoder`
reads from the image's words. Each back end carries its family's decoder
(`Backend.flow` in compiler/backend.py: the module `compiler.<family>.flow`),
so this module names no family. A decoder is independent of the assembler:
it could time any HEX file of the family.

Method, per routine (the scan; each call target on its own, so that a call
costs its callee's worst case): the control-flow graph of the instructions
the routine reaches; a loop is the natural loop of a back edge's target (its
head); innermost first, each loop becomes one node whose way out to each exit
costs (passes - 1) x the longest pass + the longest way from the head to
that exit (or, for a wait on hardware bounded in time, that time + one pass
+ the way out); the loop-free graph left is a longest-path problem. A loop
without a bound makes the scan unbounded: the reasons are collected, named
where the program can name them (the rung; for code shared by rungs, the
rung that calls it).
"""

from __future__ import annotations

import bisect
import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Protocol

from lang.devices import Device
from lang.diagnostics import Diagnostic
from lang.model import Program

from .errors import SCAN_OVERRUN, note
from .image import Image, LoopBound

NEXT, JUMP, BRANCH, SKIP, CALL, RETURN, COMPUTED = "next", "jump", "branch", "skip", "call", "return", "computed"
EXIT = -1  # the node every way out of a routine leads to
MENTIONED_SHARE = 0.1  # loops taking at least this share of the worst case are named


@dataclass(frozen=True)
class Instruction:
    """What the analysis needs of one instruction."""

    address: int  # word address
    size: int = 1  # words
    cycles: int = 1  # when it goes on to the next instruction (a branch not taken, a skip not skipping)
    flow: str = NEXT  # NEXT, JUMP, BRANCH, SKIP, CALL, RETURN or COMPUTED
    target: int | None = None  # where a jump, branch or call goes; where a skip goes when it skips
    taken: int = 0  # cycles when a branch is taken or a skip skips
    targets: tuple[int, ...] = ()  # where a computed jump may go (empty: not known)
    text: str = ""  # the mnemonic, for messages

    @property
    def next(self) -> int:
        return self.address + self.size


class Decoder(Protocol):
    """A family's reading of its program memory."""

    CLOCKS_PER_CYCLE: int  # clocks per CPU cycle: what the budget's cycles are counted in

    def instruction_at(self, words: list[int], address: int, device: Device) -> Instruction | None:
        """The instruction at a word address, None where none is encoded."""
        ...


@dataclass(frozen=True)
class LoopUse:
    """A bounded loop on the worst path: the cycles all its passes take."""

    head: int
    what: str
    cycles: int
    site: int  # the address that places it: its head, or the call that leads to it


@dataclass(frozen=True)
class Unbounded:
    """Why a routine has no bound: a loop with none (`what` None: a loop the
    back end gave no bound, such as a ladder GOTO backwards), a call of
    itself, code the decoder cannot read."""

    head: int
    what: str | None
    site: int


@dataclass
class Worst:
    """A routine's worst case. Its unbounded loops count one pass."""

    cycles: int
    loops: list[LoopUse] = field(default_factory=list)  # on the worst path (an outer loop includes its inner)
    unbounded: list[Unbounded] = field(default_factory=list)  # everything unbounded it can reach
    spent: list[tuple[int, int]] = field(default_factory=list)  # (site, cycles) along the worst path


@dataclass(frozen=True)
class _Edge:
    to: int  # an address, or EXIT
    cycles: int
    call: Worst | None = None
    loop: LoopUse | None = None


class Analysis:
    """Worst cases of the routines of one program memory."""

    def __init__(self, code: Callable[[int], Instruction | None], bounds: dict[int, LoopBound],
                 placed: Callable[[int], bool] = lambda address: True):
        self.code = code  # address -> its instruction, None where nothing can be decoded
        self.bounds = bounds  # loop-head address -> its bound
        self.placed = placed  # whether an address can be named in the program (else: its caller's site)
        self._done: dict[int | tuple[int, int], Worst] = {}
        self._active: set[int] = set()

    def routine(self, entry: int, end: int | None = None) -> Worst:
        """The worst case from `entry` to a return (or to `end`)."""
        key = entry if end is None else (entry, end)
        if key not in self._done:
            self._active.add(entry)
            try:
                self._done[key] = _Routine(self, entry, end).worst()
            finally:
                self._active.discard(entry)
        return self._done[key]

    def called(self, at: int, target: int, problems: list[Unbounded]) -> Worst:
        if target in self._active:
            problems.append(Unbounded(target, "a subroutine that calls itself", at))
            return Worst(0)
        return self.routine(target)


def _target(ins: Instruction) -> int:
    assert ins.target is not None, f"{ins.text} at word 0x{ins.address:X} decoded without its target"
    return ins.target


class _Routine:
    def __init__(self, analysis: Analysis, entry: int, end: int | None):
        self.analysis = analysis
        self.entry = entry
        self.end = end
        self.problems: list[Unbounded] = []
        self.edges: dict[int, list[_Edge]] = {EXIT: []}
        self._explore()

    def _out(self, address: int) -> list[_Edge]:
        if address == self.end:
            return [_Edge(EXIT, 0)]
        ins = self.analysis.code(address)
        if ins is None:
            self.problems.append(Unbounded(address, f"code the analysis cannot read at word 0x{address:X}",
                                           address))
            return [_Edge(EXIT, 0)]
        if ins.flow == NEXT:
            return [_Edge(ins.next, ins.cycles)]
        if ins.flow == JUMP:
            return [_Edge(_target(ins), ins.cycles)]
        if ins.flow in (BRANCH, SKIP):
            return [_Edge(ins.next, ins.cycles), _Edge(_target(ins), ins.taken)]
        if ins.flow == CALL:
            callee = self.analysis.called(address, _target(ins), self.problems)
            self.problems += [_placed(self.analysis, u, address) for u in callee.unbounded]
            return [_Edge(ins.next, ins.cycles + callee.cycles, call=callee)]
        if ins.flow == RETURN:
            return [_Edge(EXIT, ins.cycles)]
        if not ins.targets:
            self.problems.append(Unbounded(address, f"a computed jump ({ins.text}) to places the analysis "
                                                    "cannot tell", address))
            return [_Edge(EXIT, ins.cycles)]
        return [_Edge(t, ins.cycles) for t in ins.targets]

    def _explore(self) -> None:
        todo = [self.entry]
        while todo:
            address = todo.pop()
            if address in self.edges:
                continue
            self.edges[address] = self._out(address)
            todo += [e.to for e in self.edges[address] if e.to != EXIT and e.to not in self.edges]

    # --- loops ------------------------------------------------------------------------------

    def _depth_first(self) -> tuple[list[int], list[tuple[int, int]]]:
        """(reverse postorder, back edges as (source, head))."""
        order, back = [], []
        state: dict[int, int] = {}  # 1 on the stack, 2 finished
        stack = [(self.entry, iter(self.edges[self.entry]))]
        state[self.entry] = 1
        while stack:
            node, edges = stack[-1]
            for edge in edges:
                if edge.to == EXIT:
                    continue
                seen = state.get(edge.to)
                if seen == 1:
                    back.append((node, edge.to))
                elif seen is None:
                    state[edge.to] = 1
                    stack.append((edge.to, iter(self.edges[edge.to])))
                    break
            else:
                state[node] = 2
                order.append(node)
                stack.pop()
        order.reverse()
        return order, back

    def _dominators(self, order: list[int]) -> dict[int, int]:
        """Immediate dominators (Cooper, Harvey and Kennedy's iteration)."""
        index = {node: i for i, node in enumerate(order)}
        preds: dict[int, list[int]] = {node: [] for node in order}
        for node in order:
            for edge in self.edges[node]:
                if edge.to != EXIT:
                    preds[edge.to].append(node)
        idom = {self.entry: self.entry}

        def meet(a: int, b: int) -> int:
            while a != b:
                while index[a] > index[b]:
                    a = idom[a]
                while index[b] > index[a]:
                    b = idom[b]
            return a

        changed = True
        while changed:
            changed = False
            for node in order[1:]:
                done = [p for p in preds[node] if p in idom]
                new = done[0]
                for p in done[1:]:
                    new = meet(p, new)
                if idom.get(node) != new:
                    idom[node] = new
                    changed = True
        return idom

    def _loops(self) -> list[tuple[int, set[int]]]:
        """(head, body) of each natural loop, innermost first. A back edge to
        a node that does not dominate its source (a jump into a loop) is
        reported and dropped."""
        order, back = self._depth_first()
        idom = self._dominators(order)

        def dominates(a: int, b: int) -> bool:
            while b != a and idom[b] != b:
                b = idom[b]
            return b == a

        preds: dict[int, set[int]] = {}
        for node in order:
            for edge in self.edges[node]:
                preds.setdefault(edge.to, set()).add(node)
        bodies: dict[int, set[int]] = {}
        for source, head in back:
            if not dominates(head, source):
                self.problems.append(Unbounded(head, "a jump into the middle of a loop", source))
                self.edges[source] = [e for e in self.edges[source] if e.to != head]
                continue
            body = bodies.setdefault(head, {head})
            todo = [source]
            while todo:
                node = todo.pop()
                if node not in body:
                    body.add(node)
                    todo += preds.get(node, ())
        return sorted(bodies.items(), key=lambda item: len(item[1]))

    def _longest(self, start: int, nodes: set[int], skip_to: int | None) -> tuple[dict[int, int], dict]:
        """Longest distances from `start` over the edges among `nodes`
        (leaving out those back to `skip_to`) and the edge that reached each."""
        indegree = {node: 0 for node in nodes}
        for node in nodes:
            for edge in self.edges[node]:
                if edge.to in nodes and edge.to != skip_to:
                    indegree[edge.to] += 1
        dist, via, ready = {start: 0}, {}, [n for n, d in indegree.items() if d == 0]
        while ready:
            node = ready.pop()
            for edge in self.edges[node]:
                if edge.to not in nodes or edge.to == skip_to:
                    continue
                if node in dist and dist[node] + edge.cycles > dist.get(edge.to, -1):
                    dist[edge.to], via[edge.to] = dist[node] + edge.cycles, (node, edge)
                indegree[edge.to] -= 1
                if not indegree[edge.to]:
                    ready.append(edge.to)
        assert not any(indegree.values()), "a cycle left after collapsing the loops"
        return dist, via

    def _collapse(self, head: int, body: set[int]) -> None:
        """Replace the loop by its head, whose edges leave it with the cost
        of all its passes."""
        dist, _ = self._longest(head, body, head)
        one_pass = 0
        leave: dict[int, int] = {}  # exit -> the longest way to it in one pass
        for node in body:
            if node not in dist:
                continue
            for edge in self.edges[node]:
                cost = dist[node] + edge.cycles
                if edge.to == head:
                    one_pass = max(one_pass, cost)
                elif edge.to not in body:
                    leave[edge.to] = max(leave.get(edge.to, -1), cost)
        bound = self.analysis.bounds.get(head)
        what = bound.what if bound is not None else None
        edges = []
        for to, cost in leave.items():
            total = _loop_cycles(bound, one_pass, cost)
            if total is None:
                total = cost
            edges.append(_Edge(to, total, loop=LoopUse(head, what or "", total, head)))
        if _loop_cycles(bound, one_pass, 0) is None:
            self.problems.append(Unbounded(head, what, head))
        for node in body:
            self.edges[node] = []
        self.edges[head] = edges

    def worst(self) -> Worst:
        for head, body in self._loops():
            self._collapse(head, body)
        nodes = set()
        todo = [self.entry]
        while todo:
            node = todo.pop()
            if node not in nodes:
                nodes.add(node)
                todo += [e.to for e in self.edges[node]]
        dist, via = self._longest(self.entry, nodes, None)
        if EXIT not in dist:
            return Worst(0, unbounded=self.problems)
        path: list[tuple[int, _Edge]] = []
        node = EXIT
        while node in via:
            node, edge = via[node]
            path.append((node, edge))
        path.reverse()
        worst = Worst(dist[EXIT], unbounded=self.problems)
        for node, edge in path:
            worst.spent.append((node, edge.cycles))
            if edge.loop is not None:
                worst.loops.append(edge.loop)
            if edge.call is not None:
                worst.loops += [_placed(self.analysis, use, node) for use in edge.call.loops]
        return worst


def _placed(analysis: Analysis, found, call_site: int):
    """A callee's finding, placed at the call when its own site cannot be."""
    return found if analysis.placed(found.site) else replace(found, site=call_site)


def _loop_cycles(bound: LoopBound | None, one_pass: int, leave: int) -> int | None:
    """All the passes of a loop and the way out, or None without a bound."""
    if bound is None:
        return None
    costs = []
    if bound.iterations is not None:
        costs.append((max(bound.iterations, 1) - 1) * one_pass + leave)
    if bound.cycles is not None:
        costs.append(bound.cycles + one_pass + leave)
    return min(costs) if costs else None


# --- a scan's budget -----------------------------------------------------------------------------

@dataclass(frozen=True)
class Wait:
    """A kind of bounded loop on the worst path: the cycles all its passes
    take there, how many times it is entered and the rungs it is in."""

    what: str
    rungs: tuple[int, ...]
    cycles: int
    count: int = 1

    def text(self) -> str:
        if not self.rungs:
            where = ""
        elif len(self.rungs) <= 3:
            where = f" in rung{'s' if len(self.rungs) > 1 else ''} {', '.join(map(str, self.rungs))}"
        else:
            where = f" in {len(self.rungs)} rungs"
        times = f" ({self.count} times)" if self.count > 1 else ""
        return f"{self.what}{where}{times}: {self.cycles:,} cycles"


@dataclass(frozen=True)
class Budget:
    """The worst case of one scan. Cycles are the CPU's: clock cycles for
    AVR, instruction cycles (4 clocks) for PIC16."""

    cycles: int | None  # None: no bound
    cycle_hz: float  # cycles per second
    cycle_us: int  # the program's scan cycle
    loops: tuple[Wait, ...] = ()  # the loops on the worst path, the costliest first
    unbounded: tuple[str, ...] = ()  # why there is no bound: "LOCK in rung 7"
    rung: int | None = None  # the rung that takes the most on the worst path
    limit: tuple[int, str] | None = None  # Image.scan_limit: less than the cycle

    @property
    def us(self) -> float | None:
        return None if self.cycles is None else self.cycles * 1e6 / self.cycle_hz

    @property
    def dominant(self) -> tuple[Wait, ...]:
        """The (at most three) loops that take a tenth of the worst case or more."""
        if self.cycles is None:
            return ()
        return tuple(w for w in self.loops if w.cycles >= MENTIONED_SHARE * self.cycles)[:3]

    @property
    def overruns(self) -> bool:
        """A bounded worst case longer than the cycle, or than the limit of
        a cycle timer that runs free."""
        us = self.us
        return us is not None and (us > self.cycle_us or self.beyond_limit)

    @property
    def beyond_limit(self) -> bool:
        return self.cycles is not None and self.limit is not None and self.cycles > self.limit[0]

    def summary(self) -> str:
        """`scan: at most 1,234 cycles = 247 µs of the 10 ms cycle (2.5%)`."""
        us = self.us
        if us is None:
            return f"scan: no bound ({'; '.join(self.unbounded)})"
        line = (f"scan: at most {self.cycles:,} cycles = {_us(us)} of the {self.cycle_us / 1000:g} ms cycle "
                f"({100 * us / self.cycle_us:.1f}%)")
        if self.dominant:
            line += "; mostly " + ", ".join(w.text() for w in self.dominant)
        return line


def _us(us: float) -> str:
    return f"{us:,.1f} µs" if us < 100 else f"{us:,.0f} µs"


def _rung_starts(image: Image, rungs: int) -> list[tuple[int, int]]:
    """(address, rung number) where each rung's code starts, sorted; at one
    address the last label (comment rungs share the next rung's address)."""
    found: dict[int, int] = {}
    for label, address in image.labels.items():
        m = re.fullmatch(r"rung(\d+)", label)
        if m:
            found[address] = max(found.get(address, 0), int(m.group(1)))
    return sorted((a, n if n <= rungs else 0) for a, n in found.items())


def scan_budget(program: Program, device: Device, image: Image, flow: Decoder) -> Budget:
    """The worst case of one scan of a compiled image, read by its family's decoder."""
    cache: dict[int, Instruction | None] = {}

    def code(address: int) -> Instruction | None:
        if address not in cache:
            cache[address] = flow.instruction_at(image.words, address, device)
        return cache[address]

    scan, wait = image.labels["scan"], image.labels["wait"]
    starts = _rung_starts(image, len(program.rungs))
    addresses = [start for start, _ in starts]

    def rung_of(address: int) -> int | None:
        at = bisect.bisect_right(addresses, address) - 1
        return starts[at][1] or None if scan <= address < wait and at >= 0 else None

    bounds = {image.labels[name]: bound for name, bound in image.loops.items() if name in image.labels}
    rung_heads = {start: n for start, n in starts if n}
    worst = Analysis(code, bounds, lambda address: scan <= address < wait).routine(scan, wait)
    settings = program.settings
    hz = settings.crystal_hz / flow.CLOCKS_PER_CYCLE
    if worst.unbounded:
        in_order = sorted(worst.unbounded, key=lambda u: rung_of(u.site) or len(program.rungs) + 1)
        reasons = list(dict.fromkeys(_reason(u, rung_of, rung_heads) for u in in_order))
        return Budget(None, hz, settings.cycle_us, unbounded=tuple(reasons))
    by_rung: dict[int | None, int] = {}
    for site, cycles in worst.spent:
        by_rung[rung_of(site)] = by_rung.get(rung_of(site), 0) + cycles
    costliest = max((r for r in by_rung if r), key=lambda r: by_rung[r], default=None)
    return Budget(worst.cycles, hz, settings.cycle_us, _loops(worst, rung_of), rung=costliest,
                  limit=image.scan_limit)


def _reason(found: Unbounded, rung_of, rung_heads: dict[int, int]) -> str:
    rung = rung_of(found.site)
    where = f" in rung {rung}" if rung else ""
    if found.what is not None:
        return f"{found.what}{where}"
    if found.head in rung_heads:
        return f"a GOTO back to rung {rung_heads[found.head]}"
    return f"a loop at word 0x{found.head:X} without a bound{where}"


def _loops(worst: Worst, rung_of) -> tuple[Wait, ...]:
    """The loops on the worst path by kind, the costliest first."""
    grouped: dict[str, Wait] = {}
    for use in worst.loops:
        old = grouped.get(use.what, Wait(use.what, (), 0, 0))
        rung = rung_of(use.site)
        rungs = tuple(sorted(set(old.rungs) | ({rung} if rung else set())))
        grouped[use.what] = Wait(use.what, rungs, old.cycles + use.cycles, old.count + 1)
    return tuple(sorted(grouped.values(), key=lambda w: -w.cycles))


def overrun_warning(program: Program, budget: Budget) -> Diagnostic | None:
    """LD712 when the worst case does not fit the cycle, on the rung that
    takes the most."""
    us = budget.us
    if us is None or not budget.overruns:
        return None
    if us > budget.cycle_us or budget.limit is None:
        message = (f"a scan may take up to {_us(us)} ({budget.cycles:,} cycles), more than the "
                   f"{budget.cycle_us / 1000:g} ms cycle: every timer would run slow")
    else:
        cycles, what = budget.limit
        message = (f"a scan may take up to {_us(us)} ({budget.cycles:,} cycles), more than {what} "
                   f"({_us(cycles * 1e6 / budget.cycle_hz)}, {cycles:,} cycles): the cycle timer would lose "
                   "time and every timer run slow")
    if budget.dominant:
        message += "; mostly " + ", ".join(w.text() for w in budget.dominant)
    rung = program.rungs[budget.rung - 1] if budget.rung else None
    return note(SCAN_OVERRUN, message, _first_element(rung) if rung is not None else None)


def _first_element(rung):
    for element in rung.elements():
        if element.span is not None:
            return element
    return rung
