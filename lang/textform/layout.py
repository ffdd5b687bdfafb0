"""Where each part of a rung goes in LDmicro's grid: elements and padding in
cells, vertical connectors between rows. This mirrors LDmicro's own drawing
(DrawElement: series left to right, parallel branches one below the other,
end-of-line elements pushed to the last column, connectors drawn from the
lowest row whose edge cell is occupied), so a program is drawn as LDmicro
draws it."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..model import Element, Node, Series
from ..trampoline import run


@dataclass
class Placed:
    element: Element | None  # None: a padding wire
    col: int
    row: int
    cells: int = 1


@dataclass
class Grid:
    columns: int  # C for this rung: where end-of-line elements go
    placed: list[Placed] = field(default_factory=list)
    occupied: set[tuple[int, int]] = field(default_factory=set)
    # (k, row): a connector at the last character of column k (k = -1: the
    # left rail) joining row-1 and row
    connectors: set[tuple[int, int]] = field(default_factory=set)
    height: int = 1

    def put(self, element: Element | None, col: int, row: int, cells: int = 1) -> None:
        self.placed.append(Placed(element, col, row, cells))
        for k in range(col, col + cells):
            self.occupied.add((k, row))


def cells_of(element: Element) -> int:
    return element.spec.cells


def natural_width(node: Node) -> int:
    """Width in cells with end-of-line elements counted as one (how LDmicro
    measures the widest rung)."""
    return run(_natural_width(node))


def _natural_width(node: Node):
    if isinstance(node, Element):
        return cells_of(node)
    widths = []
    for child in node.items if isinstance(node, Series) else node.branches:
        widths.append((yield _natural_width(child)))
    return sum(widths) if isinstance(node, Series) else max(widths)


def height(node: Node) -> int:
    return run(_height(node))


def _height(node: Node):
    if isinstance(node, Element):
        return 1
    heights = []
    for child in node.items if isinstance(node, Series) else node.branches:
        heights.append((yield _height(child)))
    return max(heights, default=1) if isinstance(node, Series) else sum(heights)


def _width(node: Node, so_far: int, columns: int, widths: dict[tuple[int, int], int]):
    """Width while drawing: end-of-line elements stretch to the last column.
    A parallel's width is kept: placing it asks again, at the same column, and
    asking anew at every level of a deep rung would walk it once per level."""
    if isinstance(node, Element):
        if node.spec.eol:
            return max(columns - so_far, 1)
        return cells_of(node)
    if isinstance(node, Series):
        total = 0
        for item in node.items:
            total += yield _width(item, so_far + total, columns, widths)
        return total
    key = (id(node), so_far)
    if key not in widths:
        found = []
        for branch in node.branches:
            found.append((yield _width(branch, so_far, columns, widths)))
        widths[key] = max(found)
    return widths[key]


def layout(circuit: Series, columns: int) -> Grid:
    heights: dict[int, int] = {}
    grid = Grid(columns, height=run(_measure(circuit, heights)))
    run(_place(circuit, 0, 0, grid, heights, {}))
    return grid


def _measure(node: Node, heights: dict[int, int]):
    """Every block's height, once (placing a deep rung asks for them again and again)."""
    if isinstance(node, Element):
        return 1
    found = []
    for child in node.items if isinstance(node, Series) else node.branches:
        found.append((yield _measure(child, heights)))
    heights[id(node)] = max(found, default=1) if isinstance(node, Series) else sum(found)
    return heights[id(node)]


def _place(node: Node, col: int, row: int, grid: Grid, heights: dict[int, int],
           widths: dict[tuple[int, int], int]):
    if isinstance(node, Element):
        if node.spec.eol:
            while col < grid.columns - 1:
                grid.put(None, col, row)
                col += 1
        grid.put(node, col, row, cells_of(node))
        return col + cells_of(node)
    if isinstance(node, Series):
        for item in node.items:
            col = yield _place(item, col, row, grid, heights, widths)
        return col
    width = yield _width(node, col, grid.columns, widths)
    total_height = heights[id(node)]
    top = row
    for branch in node.branches:
        end = yield _place(branch, col, top, grid, heights, widths)
        while end - col < width:
            grid.put(None, end, top)
            end += 1
        top += heights.get(id(branch), 1)
    end_col = col + width
    if end_col != grid.columns:
        _connect(grid, end_col - 1, end_col - 1, row, total_height)
    _connect(grid, col, col - 1, row, total_height)
    return end_col


def _connect(grid: Grid, edge: int, at: int, row: int, total_height: int) -> None:
    """From the lowest row whose edge cell is occupied, up to the first."""
    needed = False
    for j in range(total_height - 1, 0, -1):
        if (edge, row + j) in grid.occupied:
            needed = True
        if needed:
            grid.connectors.add((at, row + j))
