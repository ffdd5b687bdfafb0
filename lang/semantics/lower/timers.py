"""Timers, counters, RES and the time converters, as LDmicro compiles them
(intcode.cpp ELEM_TON ... ELEM_CTR): accumulators count scans, each element
instance has its own edge memory."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lang.instructions import TIMERS
from lang.values import is_literal

from .. import ir
from .builder import Builder, Holds, IsSet, lowers

if TYPE_CHECKING:
    from . import PartBuilder


def limit(b: Builder, el) -> ir.Operand:
    """The timer's limit: its period in scans, or the delay variable."""
    delay = el.args["delay"]
    if isinstance(delay, int):
        return ir.Const(b.period(delay, int(el.args.get("adjust", 0) or 0), el.args["name"]))
    return b.var(str(delay))


def _increment(b: Builder, t: ir.Var) -> None:
    b.emit(ir.Arith("add", t, t, ir.Const(1)))


@lowers(*TIMERS)
def timer(b: Builder, el, p: ir.Bit) -> None:
    t, top = b.var(el.args["name"]), limit(b, el)
    below = Holds(t, "<", top)
    kind = el.kind
    if kind == "TON":
        with b.if_(IsSet(p)) as branch:
            with b.if_(below):
                b.emit(ir.SetBit(p, False))
                _increment(b, t)
            with branch.otherwise():
                b.emit(ir.Move(t, ir.Const(0)))
    elif kind == "TOF":
        with b.if_(IsSet(p, False)) as branch:
            with b.if_(below):
                _increment(b, t)
                b.emit(ir.SetBit(p, True))
            with branch.otherwise():
                b.emit(ir.Move(t, ir.Const(0)))
    elif kind == "RTO":
        with b.if_(below) as branch:
            with b.if_(IsSet(p)):
                _increment(b, t)
                b.emit(ir.SetBit(p, False))
            with branch.otherwise():
                b.emit(ir.SetBit(p, True))
    elif kind == "RTL":
        with b.if_(below) as branch:
            with b.if_(IsSet(p, False)) as inner:
                _increment(b, t)
                with inner.otherwise():
                    b.emit(ir.SetBit(p, False))
            with branch.otherwise():
                b.emit(ir.SetBit(p, True))
    elif kind == "TCY":
        phase = b.memory_bit("phase")
        with b.if_(IsSet(p)) as branch:
            with b.if_(below) as inner:
                _increment(b, t)
                with inner.otherwise():
                    b.emit(ir.Move(t, ir.Const(0)))
                    b.emit(ir.CopyBit(phase, phase, True))
            with b.if_(IsSet(phase, False)):
                b.emit(ir.SetBit(p, False))
            with branch.otherwise():
                b.emit(ir.Move(t, ir.Const(0)))
    elif kind == "THI":
        st = b.memory_bit("st")
        with b.if_(IsSet(p)):
            b.emit(ir.SetBit(st, True))
        with b.if_(IsSet(st)) as branch:
            with b.if_(below) as inner:
                _increment(b, t)
                b.emit(ir.SetBit(p, True))
                with inner.otherwise():
                    with b.if_(IsSet(p, False)):
                        b.emit(ir.Move(t, ir.Const(0)))
                        b.emit(ir.SetBit(st, False))
                    b.emit(ir.SetBit(p, False))
            with branch.otherwise():
                b.emit(ir.SetBit(p, False))
    else:  # TLO
        st, hi = b.memory_bit("st"), b.memory_bit("hi")
        with b.if_(IsSet(p, False)) as branch:
            b.emit(ir.OrBit(st, hi))
            with branch.otherwise():
                b.emit(ir.SetBit(hi, True))
        with b.if_(IsSet(st)) as branch:
            with b.if_(below) as inner:
                _increment(b, t)
                b.emit(ir.SetBit(p, False))
                with inner.otherwise():
                    with b.if_(IsSet(p)):
                        b.emit(ir.Move(t, ir.Const(0)))
                        b.emit(ir.SetBit(st, False))
                    b.emit(ir.SetBit(p, True))
            with branch.otherwise(), b.if_(IsSet(hi)):
                b.emit(ir.SetBit(p, True))


@lowers("TIME2COUNT")
def time_to_count(b: Builder, el, p: ir.Bit) -> None:
    delay = el.args["delay"]
    value = b.period(delay, 0, el.args["name"])
    with b.if_(IsSet(p)):
        b.emit(ir.Move(b.var(el.args["name"]), ir.Const(value)))


@lowers("TIME2DELAY")
def time_to_delay(b: PartBuilder, el, p: ir.Bit) -> None:
    delay = el.args["delay"]
    loops = round(delay * b.program.settings.crystal_hz / (1_000_000 * b.delay_loop_cycles))
    with b.if_(IsSet(p)):
        b.emit(ir.Move(b.var(el.args["name"]), ir.Const(loops)))


def _counter_init(b: Builder, el) -> None:
    """A variable start value is copied into the counter the first time the
    element runs (a numeric one is set before the first scan)."""
    init = str(el.args.get("init", "0"))
    if not is_literal(init):
        done, c = b.memory_bit("init"), b.var(el.args["name"])
        with b.if_(IsSet(done, False)):
            b.emit(ir.SetBit(done, True))
            b.emit(ir.Move(c, b.var(init)))


def _edge(b: Builder, el, p: ir.Bit, act, idle=None) -> None:
    """Run `act()` when the counting edge happens and `idle()` on the scans
    where the input is in its resting state (the edge kinds of intcode.cpp)."""
    kind = el.args.get("kind", "/")
    if kind in "/\\":
        st = b.memory_bit("edge")
        rising = kind == "/"
        with b.if_(IsSet(p, rising)) as branch:
            if idle:
                idle()
            with b.if_(IsSet(st, not rising)):
                b.emit(ir.SetBit(st, rising))
                act()
            with branch.otherwise():
                b.emit(ir.SetBit(st, not rising))
                if idle and not rising:
                    idle()
    else:
        with b.if_(IsSet(p, kind == "-")):
            act()


@lowers("CTU", "CTD")
def up_down_counter(b: Builder, el, p: ir.Bit) -> None:
    c, top = b.var(el.args["name"]), b.operand(el.args["max"])
    up = el.kind == "CTU"
    _counter_init(b, el)

    def step():
        with b.if_(Holds(c, "<" if up else ">", top)):
            b.emit(ir.Arith("add" if up else "sub", c, c, ir.Const(1)))

    _edge(b, el, p, step)
    b.emit(ir.SetBit(p, False))
    with b.if_(Holds(c, ">=" if up else ">", top)):
        b.emit(ir.SetBit(p, True))


@lowers("CTC", "CTR")
def circular_counter(b: Builder, el, p: ir.Bit) -> None:
    c, top = b.var(el.args["name"]), b.operand(el.args["max"])
    start = b.operand(el.args.get("init", "0"))
    up = el.kind == "CTC"
    past = Holds(c, ">" if up else "<", top)
    kind = el.args.get("kind", "/")
    _counter_init(b, el)

    def step():
        b.emit(ir.Arith("add" if up else "sub", c, c, ir.Const(1)))

    if kind == "-":
        # LDmicro's code leaves the rung true on the wrap (its "impulse" is
        # the input itself) and clears it otherwise
        with b.if_(IsSet(p)):
            step()
            with b.if_(past) as branch:
                b.emit(ir.Move(c, start))
                with branch.otherwise():
                    b.emit(ir.SetBit(p, False))
        return

    def wrapped():
        step()
        with b.if_(past):
            b.emit(ir.Move(c, start))
            b.emit(ir.SetBit(p, True))

    if kind == "o":
        with b.if_(IsSet(p, False)) as branch:
            wrapped()
            with branch.otherwise():
                b.emit(ir.SetBit(p, False))
        return
    _edge(b, el, p, wrapped, idle=lambda: b.emit(ir.SetBit(p, False)))


@lowers("RES")
def reset(b: PartBuilder, el, p: ir.Bit) -> None:
    name = el.args["name"]
    if name.startswith("P"):
        with b.if_(IsSet(p)):
            b.emit(ir.PwmOff(b.pwm_unit(name)))
            b.emit(ir.SetBit(b.bit(name), False))
        return
    target = b.var(name)
    value: ir.Operand = ir.Const(0)
    if name.startswith("C"):
        counter = b.counter_defs.get(name)
        if counter is not None:
            value = b.operand(counter.args.get("init", "0"))
    with b.if_(IsSet(p)):
        b.emit(ir.Move(target, value))

