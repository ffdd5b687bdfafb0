"""From wires to a circuit: a rung drawn as a graph between the rails is
reduced to series and parallel blocks, or its non-series/parallel shape is
reported where it is."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..model import Node, Parallel, Series, Span

LEFT = 0
RIGHT = 1


class Nodes:
    """Electrical nodes: union-find over wire ends and junctions."""

    def __init__(self) -> None:
        self.parent = [LEFT, RIGHT]
        self.where: dict[int, Span] = {}

    def new(self, where: Span | None = None) -> int:
        self.parent.append(len(self.parent))
        if where is not None:
            self.where[len(self.parent) - 1] = where
        return len(self.parent) - 1

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


@dataclass
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
    while True:
        if len(edges) == 1 and (edges[0].start, edges[0].end) == (LEFT, RIGHT):
            return edges[0].node
        changed = _merge_parallel(edges) | _merge_series(edges)
        if not changed:
            break
    raise NotSeriesParallel("the branches do not form series and parallel blocks", _culprit(edges, nodes))


def _merge_parallel(edges: list[Edge]) -> bool:
    groups: dict[tuple[int, int], list[Edge]] = {}
    for edge in edges:
        groups.setdefault((edge.start, edge.end), []).append(edge)
    changed = False
    for group in groups.values():
        if len(group) < 2:
            continue
        group.sort(key=lambda e: e.order)
        branches: list[tuple[tuple[int, int], Node]] = []
        for edge in group:
            branches.extend(edge.branches or [(edge.order, edge.node)])
        branches.sort(key=lambda item: item[0])
        span = group[0].span
        for edge in group[1:]:
            span = span.union(edge.span)
        merged = Edge(group[0].start, group[0].end, Parallel([b for _, b in branches], span),
                      group[0].order, span, branches)
        for edge in group:
            edges.remove(edge)
        edges.append(merged)
        changed = True
    return changed


def _merge_series(edges: list[Edge]) -> bool:
    incoming: dict[int, list[Edge]] = {}
    outgoing: dict[int, list[Edge]] = {}
    for edge in edges:
        outgoing.setdefault(edge.start, []).append(edge)
        incoming.setdefault(edge.end, []).append(edge)
    for node, ins in incoming.items():
        if node in (LEFT, RIGHT) or len(ins) != 1 or len(outgoing.get(node, ())) != 1:
            continue
        first, second = ins[0], outgoing[node][0]
        if first is second:
            continue
        items: list[Node] = []
        for part in (first.node, second.node):
            items.extend(part.items if isinstance(part, Series) else [part])
        span = first.span.union(second.span)
        edges.remove(first)
        edges.remove(second)
        edges.append(Edge(first.start, second.end, Series(items, span), min(first.order, second.order), span))
        return True
    return False


def _culprit(edges: list[Edge], nodes: Nodes) -> Span:
    """Where to point: a junction joining more than a series/parallel allows,
    else the first element left over."""
    degree: dict[int, int] = {}
    for edge in edges:
        degree[edge.start] = degree.get(edge.start, 0) + 1
        degree[edge.end] = degree.get(edge.end, 0) + 1
    for node, _ in sorted(degree.items(), key=lambda item: -item[1]):
        if node not in (LEFT, RIGHT):
            for member, span in nodes.where.items():
                if nodes.find(member) == node:
                    return span
    return min(edges, key=lambda e: e.order).span
