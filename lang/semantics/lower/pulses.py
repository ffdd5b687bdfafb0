"""PULSER, LDmicro's pulse generator, as its intcode.cpp compiles it: on
the input's rising edge it starts `counter` pulses of `p1` scans high and
`p0` scans low, each stretched `accel` times at the start and the end and
shortened by a scan a pulse in between (the ramps), and passes power while
it runs. Its working variables are LDmicro's, of LDmicro's size (2 bytes).

And NPULSE OFF, which stops the N PULSE generator."""

from __future__ import annotations

from lang.values import is_literal

from .. import ir
from .builder import Builder, Holds, IsSet, lowers

WORK = 2  # the size of LDmicro's generated variables ($var_...)


def _mode(b: Builder, el) -> str:
    """LDmicro's "Meander": 'square' (1, 1, 1: the output toggles every scan),
    'even' (equal literal high and low times) or 'ramped' (any other)."""
    p1, p0, accel = (str(el.args[f]) for f in ("p1", "p0", "accel"))
    if not (is_literal(p1) and is_literal(p0)):
        return "ramped"
    if b.literal(p1) == b.literal(p0) == 1 and is_literal(accel) and b.literal(accel) == 1:
        return "square"
    return "even" if b.literal(p1) == b.literal(p0) else "ramped"


@lowers("PULSER")
def pulser(b: Builder, el, p: ir.Bit) -> None:
    mode = _mode(b, el)
    p1, p0, accel, count = (b.operand(el.args[f]) for f in ("p1", "p0", "accel", "counter"))
    coil = b.bit(str(el.args["coil"]))
    busy, high, reload = b.memory_bit("busy"), b.memory_bit("osc"), b.memory_bit("reload")
    left, ramp_end, t1, t0, work1, work0 = (b.memory_var(what, WORK) for what in
                                             ("left", "decel", "t1", "t0", "work1", "work0"))

    def dec(var: ir.Var) -> None:
        b.emit(ir.Arith("sub", var, var, ir.Const(1)))

    with b.if_(IsSet(p)) as powered:
        with b.if_(IsSet(busy, False)):
            b.emit(ir.SetBit(busy, True))
            b.emit(ir.SetBit(high, True))
            b.emit(ir.Move(left, count))
            b.emit(ir.Move(ramp_end, accel))
            dec(ramp_end)
            b.emit(ir.Arith("mul", ramp_end, p1, ramp_end))
            if mode != "square":
                b.emit(ir.SetBit(reload, False))
                b.emit(ir.Arith("mul", t1, p1, accel))
                b.emit(ir.Move(work1, t1))
                if mode == "ramped":
                    b.emit(ir.Arith("mul", t0, p0, accel))
                    b.emit(ir.Move(work0, t0))
        with powered.otherwise():
            b.emit(ir.CopyBit(p, busy))
    with b.if_(IsSet(busy)):
        if mode == "square":
            with b.if_(IsSet(high)) as on:
                b.emit(ir.SetBit(coil, True))
                b.emit(ir.SetBit(high, False))
                with on.otherwise():
                    b.emit(ir.SetBit(coil, False))
                    b.emit(ir.SetBit(high, True))
                    dec(left)
        elif mode == "even":
            b.emit(ir.CopyBit(coil, high))
            dec(work1)
            with b.if_(Holds(work1, "<", ir.Const(1))):
                with b.if_(IsSet(high)) as on:
                    b.emit(ir.SetBit(high, False))
                    with on.otherwise():
                        b.emit(ir.SetBit(high, True))
                        dec(left)
                b.emit(ir.SetBit(reload, True))
            with b.if_(IsSet(reload)):
                b.emit(ir.SetBit(reload, False))
                with b.if_(IsSet(high)):
                    _ramp(b, left, ramp_end, ((t1, p1, None),))
                b.emit(ir.Move(work1, t1))
        else:
            dec(work1)
            with b.if_(Holds(work1, "<", ir.Const(0))) as low:
                b.emit(ir.SetBit(coil, False))
                dec(work0)
                with b.if_(Holds(work0, "<", ir.Const(1))):
                    dec(left)
                    b.emit(ir.SetBit(reload, True))
                with low.otherwise():
                    b.emit(ir.SetBit(coil, True))
            with b.if_(IsSet(reload)):
                b.emit(ir.SetBit(reload, False))
                _ramp(b, left, ramp_end, ((t1, p1, work1), (t0, p0, work0)))
        with b.if_(Holds(left, "<", ir.Const(1))):
            b.emit(ir.SetBit(busy, False))


def _ramp(b: Builder, left: ir.Var, ramp_end: ir.Var, times) -> None:
    """Before the last `accel` pulses each time shrinks by a scan down to its
    base value; from there each grows by a scan. `times`: (time, base, the
    working copy loaded here or None)."""
    with b.if_(Holds(left, ">", ramp_end)) as speeding:
        for time, base, work in times:
            with b.if_(Holds(time, ">", base)):
                b.emit(ir.Arith("sub", time, time, ir.Const(1)))
            if work is not None:
                b.emit(ir.Move(work, time))
        with speeding.otherwise():
            for time, _, work in times:
                b.emit(ir.Arith("add", time, time, ir.Const(1)))
                if work is not None:
                    b.emit(ir.Move(work, time))


@lowers("NPULSE_OFF")
def npulse_off(b: Builder, el, p: ir.Bit) -> None:
    """No code: the generator it stops never runs. LDmicro refuses every
    program with an N PULSE (docs/compiler.md), and so do we; in the AVR
    images LDmicro makes of NPULSE OFF alone, it clears an interrupt enable
    bit that nothing sets, between a CLI and an SEI."""
