"""STEPPER, LDmicro's stepper-motor pulse generator, as its intcode.cpp
compiles it: the input's rising edge, when the last run is over, starts
`max` step pulses on the coil, one every `p` scans, and with an acceleration
curve (`graph` 1..6 over `size` steps) the first and last steps slower along
LDmicro's table (lang/semantics/acceleration.py). A pulse rises and falls
within the scan, as in LDmicro's code. The element passes power while steps
remain. The working variables are LDmicro's: C<name>Dec (steps left),
C<name>Inc (steps made) and C<name>P (scans to the next step)."""

from __future__ import annotations

from dataclasses import dataclass

from lang.numbers import byte_needed
from lang.values import is_literal

from .. import ir
from ..acceleration import GRAPHS, steps
from .builder import Builder, Holds, IsSet, lowers

# LDmicro's four forms: a step every scan, every p scans, along the table
# with a literal p, along the table scaled by a variable p
EVERY_SCAN, EVERY_P, TABLE, SCALED = 1, 2, 3, 4


@dataclass(frozen=True)
class _Plan:
    form: int
    table: tuple[int, ...]
    shift: int
    counter_size: int  # C<name>Dec and C<name>Inc: max's
    wait_size: int  # C<name>P: a table entry's or p's, the larger
    entry_size: int  # a table entry's (LDmicro's sovElement), at least 1


def _plan(b: Builder, el) -> _Plan:
    period, count = str(el.args["p"]), str(el.args["max"])
    graph = int(el.args["graph"])
    literal = is_literal(period)
    ramp = steps(int(el.args["size"]), graph, b.literal(period) if literal else 0) if graph in GRAPHS else None
    table = ramp.table if ramp else ()
    # LDmicro's choice (intcode.cpp's `speed`); a table of one step or none is
    # no ramp (LDmicro reads before its empty table when the period is a
    # variable: docs/semantics.md)
    if len(table) >= 2:
        form = TABLE if literal else SCALED
    else:
        form = EVERY_SCAN if literal and b.literal(period) == 1 else EVERY_P
    entry_size = ramp.element_size if ramp else 0
    p_size = byte_needed(b.literal(period)) if literal else b.size(period)
    counter_size = byte_needed(b.literal(count)) if is_literal(count) else b.size(count)
    return _Plan(form, table, ramp.shift if ramp else 0, counter_size, max(entry_size, p_size), max(entry_size, 1))


def _named(b: Builder, name: str, size: int) -> ir.Var:
    """LDmicro's working variable `name`, of LDmicro's size unless the
    program names it too (then the program's variable is the one)."""
    if name in b.sizes:
        return b.var(name)
    b.vars[name] = size
    return ir.Var(name, size)


@lowers("STEPPER")
def stepper(b: Builder, el, p: ir.Bit) -> None:
    name = str(el.args["name"])
    plan = _plan(b, el)
    form, table = plan.form, plan.table
    # STEPPERs of one name share its counters (as in LDmicro): each counter
    # takes the largest size any of them needs
    shared = [_plan(b, other) for _, other in b.program.elements()
              if other.kind == "STEPPER" and str(other.args["name"]) == name]
    count, p_operand = b.operand(el.args["max"]), b.operand(el.args["p"])
    counter_size = max(s.counter_size for s in shared)
    left = _named(b, f"C{name}Dec", counter_size)
    made = _named(b, f"C{name}Inc", counter_size)
    wait = _named(b, f"C{name}P", max(s.wait_size for s in shared))
    full_speed = b.memory_var("tmul", plan.entry_size)
    coil = b.bit(str(el.args["coil"]))
    edge = b.memory_bit("edge")

    def dec(var: ir.Var) -> None:
        b.emit(ir.Arith("sub", var, var, ir.Const(1)))

    def pulse() -> None:
        b.emit(ir.SetBit(coil, True))
        dec(left)
        b.emit(ir.SetBit(coil, False))

    with b.if_(IsSet(p)) as powered:
        with b.if_(IsSet(edge, False)):
            b.emit(ir.SetBit(edge, True))
            with b.if_(Holds(left, "<", ir.Const(1))):
                b.emit(ir.Move(left, count))
                if form != EVERY_SCAN:
                    b.emit(ir.Move(wait, ir.Const(1)))
                if form in (TABLE, SCALED):
                    b.emit(ir.Move(made, ir.Const(0)))
                    b.emit(ir.Move(full_speed, ir.Const(table[-1])))
        with powered.otherwise():
            b.emit(ir.SetBit(edge, False))
    with b.if_(Holds(left, "<", ir.Const(1))) as idle:
        b.emit(ir.SetBit(p, False))
        with idle.otherwise():
            b.emit(ir.SetBit(p, True))
            if form == EVERY_SCAN:
                pulse()
            else:
                dec(wait)
                with b.if_(Holds(wait, "<", ir.Const(1))):
                    if form == EVERY_P:
                        pulse()
                        b.emit(ir.Move(wait, p_operand))
                    else:
                        b.emit(ir.SetBit(coil, True))
    if form in (TABLE, SCALED):
        # the step made above ends here: the next wait comes from the table,
        # read backwards over the last steps, forwards over the first
        n = ir.Const(len(table))
        with b.if_(IsSet(coil)):
            b.emit(ir.SetBit(coil, False))
            with b.if_(Holds(left, "<", n)) as slowing:
                b.emit(ir.Table(wait, table, left))
                with slowing.otherwise(), b.if_(Holds(made, "<", n)) as speeding:
                    b.emit(ir.Table(wait, table, made))
                    with speeding.otherwise():
                        b.emit(ir.Move(wait, full_speed))
            b.emit(ir.Arith("add", made, made, ir.Const(1)))
            dec(left)
            if form == SCALED:
                b.emit(ir.Arith("mul", wait, wait, p_operand))
                if plan.shift:
                    b.emit(ir.Shift("shr", wait, wait, ir.Const(plan.shift), wait.size))
