"""From wires to a circuit: a rung drawn as a graph between the rails is
reduced to series and parallel blocks, or its non-series/parallel shape is
reported where it is."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

from ..model import Node, Parallel, Series, Span, children, new_span

LEFT = 0
RIGHT = 1


class Nodes:
    """Electrical nodes: union-find over wire ends and junctions."""

    def __init__(self) -> None:
        self.parent = [LEFT, RIGHT]
        # (line, column) of each node's cell: a Span only for the error that names one
        self.where: dict[int, tuple[int, int]] = {}

    def new(self, line: int, col: int) -> int:
        node = len(self.parent)
        self.parent.append(node)
        self.where[node] = (line, col)
        return node

    def find(self, node: int) -> int:
        while self.parent[node] != node:
            self.parent[node] = self.parent[self.parent[node]]
            node = self.parent[node]
        return node

    def union(self, a: int, b: int) -> None:
        a, b = self.find(a), self.find(b)
        if a == b:
            return
        # the rails stay the representatives of their classes
        if b in (LEFT, RIGHT):
            a, b = b, a
        self.parent[b] = a


@dataclass(slots=True)
class Edge:
    start: int
    end: int
    node: Node
    order: tuple[int, int]  # source position of its first element: branch order
    span: Span = field(compare=False)
    # for a parallel: its branches with their own positions, so that branches
    # merged in several steps still come out top to bottom
    branches: list[tuple[tuple[int, int], Node]] = field(default_factory=list)


class NotSeriesParallel(Exception):
    def __init__(self, message: str, span: Span):
        super().__init__(message)
        self.span = span


def reduce(edges: list[Edge], nodes: Nodes) -> Node:
    """Series/parallel reduction between the rails; branch order is kept
    top to bottom. Raises NotSeriesParallel with the place of the problem."""
    for edge in edges:
        edge.start, edge.end = nodes.find(edge.start), nodes.find(edge.end)
        if edge.start == edge.end:
            raise NotSeriesParallel(
                "this element is bypassed by a bare wire (a branch without any element)", edge.span
            )
    row = _row(edges)
    if row is not None:
        return row
    ordered = sorted(edges, key=lambda edge: edge.order) if len(edges) <= _MAX_PLANNED_EDGES else []
    shape = _shape(ordered)
    plan = _PLANS.get(shape) if ordered else None
    if plan is not None:
        return build(plan, [edge.node for edge in ordered])
    left = _Reduction(edges).run()
    if len(left) == 1 and (left[0].start, left[0].end) == (LEFT, RIGHT):
        if ordered:
            _remember(shape, plan_of(left[0].node, {id(edge.node): index for index, edge in enumerate(ordered)}))
        return left[0].node
    raise NotSeriesParallel("the branches do not form series and parallel blocks", _culprit(left, nodes))


# The reduction of a shape, by shape: a program repeats a few shapes of rung
# (a parallel of three contacts before a coil...) with other names, and
# building a circuit from its plan costs a fraction of reducing it again.
# A shape is the edges in source order, their nodes numbered in order of
# first use (the rails keep 0 and 1): the reduction depends on nothing else,
# as it merges by nodes and orders branches by source position.
# Bounded, as the plans live as long as the process: a few shapes of a
# program's size are what repeats (a tall rung of thousands of rows is
# one of a kind and reduces in linear time).
Plan = tuple[tuple[int, int], ...]  # see plan_of
BlockSpans = tuple["tuple[int, int, int, int] | None", ...]  # see block_spans
_PLANS: dict[tuple[int, ...], Plan] = {}
_MAX_PLANS = 1024
_MAX_PLANNED_EDGES = 128
_LEAF, _SERIES, _PARALLEL = 0, 1, 2


def _shape(ordered: list[Edge]) -> tuple[int, ...]:
    numbers = {LEFT: LEFT, RIGHT: RIGHT}
    shape: list[int] = []
    for edge in ordered:
        shape.append(numbers.setdefault(edge.start, len(numbers)))
        shape.append(numbers.setdefault(edge.end, len(numbers)))
    return tuple(shape)


def _remember(shape: tuple[int, ...], plan: Plan) -> None:
    if len(_PLANS) >= _MAX_PLANS:
        _PLANS.pop(next(iter(_PLANS)), None)  # the oldest: enough for the shapes of one program
    _PLANS[shape] = plan


def _post_order(root: Node) -> list[tuple[Node, int]]:
    """The circuit's nodes in post-order, each with its number of children
    (0: an element). A loop, not recursion: blocks may nest a thousand deep."""
    found: list[tuple[Node, int]] = []
    stack: list[tuple[Node, bool]] = [(root, False)]
    while stack:
        node, children_done = stack.pop()
        if isinstance(node, Series | Parallel) and not children_done:
            stack.append((node, True))
            stack.extend((child, False) for child in reversed(children(node)))
        else:
            found.append((node, len(children(node)) if isinstance(node, Series | Parallel) else 0))
    return found


def plan_of(root: Node, index: dict[int, int]) -> Plan:
    """The circuit as steps in post-order: (_LEAF, the element's index among
    the edges), (_SERIES or _PARALLEL, how many nodes built before it are its
    children)."""
    return tuple((_SERIES, count) if isinstance(node, Series) else (_PARALLEL, count) if isinstance(node, Parallel)
                 else (_LEAF, index[id(node)]) for node, count in _post_order(root))


def block_spans(root: Node, line: int) -> BlockSpans | None:
    """Each step of the circuit's plan (plan_of): a block's span with its
    lines counted from `line`, None for an element; None when a block has
    no span."""
    found: list[tuple[int, int, int, int] | None] = []
    for node, _ in _post_order(root):
        if not isinstance(node, Series | Parallel):
            found.append(None)
            continue
        span = node.span
        if span is None:
            return None
        found.append((span[0] - line, span[1], span[2] - line, span[3]))
    return tuple(found)


def build(plan: Plan, leaves: list[Node]) -> Node:
    """The circuit a plan describes over these elements: new blocks, each
    spanning its children, as the reduction would have made them."""
    built: list[Node] = []
    for step, value in plan:
        if step == _LEAF:
            built.append(leaves[value])
            continue
        parts = built[-value:]
        del built[-value:]
        span = parts[0].span
        assert span is not None  # the edges' nodes are placed elements
        for part in parts[1:]:
            span = span.union(part.span)
        built.append(Series(parts, span) if step == _SERIES else Parallel(parts, span))
    return built[0]


def build_at(plan: Plan, leaves: list[Node], spans: BlockSpans, line: int) -> Node:
    """`build`'s circuit where each block's span is known (block_spans of a
    rung drawn the same way, its lines counted from `line`): a rung made
    from a recipe (lang/textform/rungs.py) places its blocks without joining
    their children's spans."""
    built: list[Node] = []
    new = new_span
    for (step, value), span in zip(plan, spans):
        if step == _LEAF:
            built.append(leaves[value])
            continue
        parts = built[-value:]
        del built[-value:]
        assert span is not None  # a block's step has its span
        placed = new(Span, (line + span[0], span[1], line + span[2], span[3]))
        built.append(Series(parts, placed) if step == _SERIES else Parallel(parts, placed))
    return built[0]


def _row(edges: list[Edge]) -> Node | None:
    """The circuit of edges that make one path from rail to rail, in order
    (most rungs: one row, no branch), as the reduction would give it; None
    for any other shape."""
    if edges[0].start != LEFT or edges[-1].end != RIGHT:
        return None
    for before, after in zip(edges, edges[1:]):
        if before.end != after.start:
            return None
    if len(edges) == 1:
        return edges[0].node
    if len({edge.start for edge in edges} - {RIGHT}) != len(edges):
        return None  # a node left twice: not a simple path
    span = edges[0].span
    for edge in edges[1:]:
        span = span.union(edge.span)
    return Series([edge.node for edge in edges], span)


class _Reduction:
    """The edges indexed by node and by pair of nodes, and a queue of what a
    merge may have made mergeable: each merge costs only the edges it takes,
    so a rung thousands of rows tall reduces in linear time. The result does
    not depend on the order of the merges (series and parallel blocks are
    flattened, branches sorted by position)."""

    def __init__(self, edges: list[Edge]):
        self.into: dict[int, dict[int, Edge]] = {}
        self.out: dict[int, dict[int, Edge]] = {}
        self.between: dict[tuple[int, int], dict[int, Edge]] = {}
        # a node (int): is it a series joint now? a pair (tuple): parallel edges to merge?
        self.queue: deque[int | tuple[int, int]] = deque()
        for edge in edges:
            self.add(edge)

    def add(self, edge: Edge) -> None:
        self.out.setdefault(edge.start, {})[id(edge)] = edge
        self.into.setdefault(edge.end, {})[id(edge)] = edge
        self.between.setdefault((edge.start, edge.end), {})[id(edge)] = edge
        self.queue.extend(((edge.start, edge.end), edge.start, edge.end))

    def remove(self, edge: Edge) -> None:
        del self.out[edge.start][id(edge)]
        del self.into[edge.end][id(edge)]
        del self.between[(edge.start, edge.end)][id(edge)]
        self.queue.extend((edge.start, edge.end))

    def run(self) -> list[Edge]:
        """The edges no merge applies to, in source order."""
        while self.queue:
            item = self.queue.popleft()
            if isinstance(item, tuple):
                self.merge_parallel(item)
            else:
                self.merge_series(item)
        return sorted((edge for group in self.between.values() for edge in group.values()),
                      key=lambda edge: edge.order)

    def merge_parallel(self, pair: tuple[int, int]) -> None:
        group = sorted(self.between.get(pair, {}).values(), key=lambda e: e.order)
        if len(group) < 2:
            return
        branches: list[tuple[tuple[int, int], Node]] = []
        for edge in group:
            branches.extend(edge.branches or [(edge.order, edge.node)])
        branches.sort(key=lambda item: item[0])
        span = group[0].span
        for edge in group:
            span = span.union(edge.span)
            self.remove(edge)
        self.add(Edge(pair[0], pair[1], Parallel([b for _, b in branches], span), group[0].order, span, branches))

    def merge_series(self, node: int) -> None:
        ins, outs = self.into.get(node, {}), self.out.get(node, {})
        if node in (LEFT, RIGHT) or len(ins) != 1 or len(outs) != 1:
            return
        (first,), (second,) = ins.values(), outs.values()
        if first is second:
            return
        # a series in an edge was made by a merge here and belongs to that
        # edge alone: it grows in place, so a long row is not copied again
        # and again
        items: list[Node] = first.node.items if isinstance(first.node, Series) else [first.node]
        items.extend(second.node.items if isinstance(second.node, Series) else [second.node])
        span = first.span.union(second.span)
        self.remove(first)
        self.remove(second)
        self.add(Edge(first.start, second.end, Series(items, span), min(first.order, second.order), span))


def _culprit(edges: list[Edge], nodes: Nodes) -> Span:
    """Where to point: a junction joining more than a series/parallel allows,
    else the first element left over."""
    degree: dict[int, int] = {}
    for edge in edges:
        degree[edge.start] = degree.get(edge.start, 0) + 1
        degree[edge.end] = degree.get(edge.end, 0) + 1
    for node, _ in sorted(degree.items(), key=lambda item: -item[1]):
        if node not in (LEFT, RIGHT):
            for member, (line, col) in nodes.where.items():
                if nodes.find(member) == node:
                    return Span.at(line, col)
    return min(edges, key=lambda e: e.order).span
