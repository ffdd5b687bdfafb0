"""The variables no write can make negative, read from the intermediate
code: a timer's or a counter's count that only the element itself writes.

A signed comparison of such a variable with a constant c >= 0 is the
unsigned one, so the baseline assembler leaves out its sign fix-up (asm.py).
Every write of the variable must be one of:

* a Move of a constant;
* an add of 1 right after a jump taken when it is at least a limit L (a
  timer counting up to its limit): the sum is at most L;
* an add of 1 right before a jump taken when it is at most M, followed by
  a Move of a constant (CTC wrapping round): the sum is at most M + 1, or
  one more than the largest value another write leaves, for the one
  comparison until the Move, and at most M after.

and the constants, the limits L and M + 1 (one more than the largest of
them all where a CTC adds) must lie in [0, the largest positive value of
the variable's size]; the RAM starts at 0. Any other
write (arithmetic, a byte of it, a routine's result, the EEPROM) and the
variable is left out. Only what lies between the guard and the add may be
notes and bit operations: a label there could bring another path in.
"""

from __future__ import annotations

from dataclasses import dataclass

from lang.semantics import ir

WRITES = ("dst", "remainder", "var")  # the fields through which an op writes a variable
BETWEEN = (ir.Note, ir.SetBit, ir.CopyBit, ir.AndBit, ir.OrBit)  # change no variable, bring no path in


def never_negative(code: ir.Code) -> frozenset[str]:
    """The names of the variables whose every write keeps them at 0 or more."""
    ops = ir.flatten(code.init) + ir.flatten(code.scan)
    bounds: dict[str, list[int]] = {name: [0] for name in code.vars}
    wrapping: set[str] = set()  # a CTC adds to it: its sum may pass the largest other value by one
    for index, op in enumerate(ops):
        for field in WRITES:
            target = getattr(op, field, None)
            if isinstance(target, ir.Byte):
                bounds.pop(target.var.name, None)
            elif isinstance(target, ir.Var) and target.name in bounds:
                write = _write(ops, index, op, target)
                if write is None:
                    bounds.pop(target.name)
                    continue
                bounds[target.name].append(write.bound)
                if write.wraps:
                    wrapping.add(target.name)
    return frozenset(name for name, values in bounds.items()
                     if min(values) >= 0 and max(values) + (name in wrapping) < 1 << (8 * code.vars[name] - 1))


@dataclass(frozen=True)
class Write:
    bound: int  # the largest value it leaves (negative: it may leave a negative one)
    wraps: bool = False  # a CTC's add, whose sum the test after it may see one past the largest value


def _write(ops: list[ir.Op], index: int, op: ir.Op, var: ir.Var) -> Write | None:
    """What the write leaves, None when it is not one of the three kinds."""
    if isinstance(op, ir.Move) and op.dst == var and isinstance(op.src, ir.Const):
        return Write(op.src.value if op.src.value >= 0 else -1)
    if not (isinstance(op, ir.Arith) and op.op == "add" and op.dst == var and op.a == var
            and op.b == ir.Const(1)):
        return None
    guard = _neighbour(ops, index, -1)
    if isinstance(guard, ir.JumpIf) and guard.a == var and guard.rel == ">=" and isinstance(guard.b, ir.Const):
        return Write(guard.b.value)
    check = _neighbour(ops, index, 1)
    if isinstance(check, ir.JumpIf) and check.a == var and check.rel == "<=" and isinstance(check.b, ir.Const):
        after = _neighbour(ops, ops.index(check, index), 1)
        if isinstance(after, ir.Move) and after.dst == var and isinstance(after.src, ir.Const):
            return Write(check.b.value + 1, wraps=True)
    return None


def _neighbour(ops: list[ir.Op], index: int, step: int) -> ir.Op | None:
    """The op before (step -1) or after (+1) `index`, past notes and bit operations."""
    at = index + step
    while 0 <= at < len(ops) and isinstance(ops[at], BETWEEN):
        at += step
    return ops[at] if 0 <= at < len(ops) else None
