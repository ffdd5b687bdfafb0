"""Facts about intermediate code that every back end needs to place storage
and write control flow: pure functions of `ir` ops and `ir.Code`."""

from __future__ import annotations

from collections.abc import Callable

from lang.numbers import byte_needed
from lang.semantics import ir

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
        elif isinstance(op, ir.Call) or (isinstance(op, ir.JUMPS) and op.target in seen):
            loops.add(op.target)
    return loops


def uses_uart(code: ir.Code) -> bool:
    return any(isinstance(op, UART_OPS) for op in code.scan)


def value_size(operand: ir.Operand, stored: Callable[[ir.Var], int]) -> int:
    """Bytes that hold the operand's value as a signed number: a constant's
    own, 2 for one unsigned byte of a variable, else the variable's size in
    memory (`stored`)."""
    if isinstance(operand, ir.Const):
        return byte_needed(operand.value)
    if isinstance(operand, ir.Byte):
        return 2
    return stored(operand)


def target_size(target: ir.Place, stored: Callable[[ir.Var], int]) -> int:
    return 1 if isinstance(target, ir.Byte) else stored(target)


def constant_bit(operand: ir.Var | ir.Byte, k: int, stored: Callable[[ir.Var], int]) -> tuple[int, int] | None:
    """(byte offset in the operand, bit) that bit number `k` of the operand
    reads: None below 0 (no bit: it reads 0), the sign bit past its width."""
    if k < 0:
        return None
    width = 1 if isinstance(operand, ir.Byte) else stored(operand)
    k = min(k, 8 * width - 1)
    return k // 8, k % 8
