"""Facts about intermediate code that every back end needs to place storage
and write control flow: pure functions of `ir` ops and `ir.Code`."""

from __future__ import annotations

from . import ir

UART_OPS = (ir.UartSend, ir.UartReady, ir.UartAvailable, ir.UartTake)


def live_intervals(ops: list[ir.Op], names: set[str]) -> dict[str, tuple[int, int]]:
    """(first, last) op index at which each of the bits `names` is read or
    written; bits never used are absent."""
    spans: dict[str, tuple[int, int]] = {}
    for i, op in enumerate(ops):
        for bit in op.reads() + op.writes():
            if bit.name in names:
                first, _ = spans.get(bit.name, (i, i))
                spans[bit.name] = (first, i)
    return spans


def use_counts(ops: list[ir.Op], names: set[str]) -> dict[str, int]:
    """How many reads and writes of each of the bits `names` the ops make."""
    counts = dict.fromkeys(names, 0)
    for op in ops:
        for bit in op.reads() + op.writes():
            if bit.name in counts:
                counts[bit.name] += 1
    return counts


def loop_labels(ops: list[ir.Op]) -> set[str]:
    """Labels entered by a jump from later code or by a call: what is known
    about storage on the way in must not be trusted there."""
    seen: set[str] = set()
    loops: set[str] = set()
    for op in ops:
        if isinstance(op, ir.Label):
            seen.add(op.name)
        elif isinstance(op, ir.Call) or (getattr(op, "target", None) in seen):
            loops.add(op.target)
    return loops


def uses_uart(code: ir.Code) -> bool:
    return any(isinstance(op, UART_OPS) for op in code.scan)
