"""Contacts, coils, edge elements, comparisons, bit tests and program flow.
Each follows the intermediate code LDmicro compiles for it (intcode.cpp), so
that the simulation matches the MCU scan for scan."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lang.instructions import RELATIONS
from lang.values import is_literal

from .. import ir
from .builder import Builder, Holds, IsSet, lowers

if TYPE_CHECKING:
    from . import PartBuilder


@lowers("CONTACTS")
def contacts(b: Builder, el, p: ir.Bit) -> None:
    b.emit(ir.AndBit(p, b.bit(el.args["name"]), bool(el.args.get("negated"))))


@lowers("COIL")
def coil(b: Builder, el, p: ir.Bit) -> None:
    bit = b.bit(el.args["name"])
    kind = el.args.get("type", " ")
    if kind in " /":
        b.emit(ir.CopyBit(bit, p, kind == "/"))
    elif kind in "SR":
        with b.if_(IsSet(p)):
            b.emit(ir.SetBit(bit, kind == "S"))
    else:  # toggle on each rising edge of the rung
        seen = b.memory_bit("toggle")
        with b.if_(IsSet(p)) as branch:
            with b.if_(IsSet(seen, False)):
                b.emit(ir.SetBit(seen, True))
                b.emit(ir.CopyBit(bit, bit, True))
            with branch.otherwise():
                b.emit(ir.SetBit(seen, False))


@lowers("OSR")
def one_shot_rising(b: Builder, el, p: ir.Bit) -> None:
    st = b.memory_bit("st")
    with b.if_(IsSet(p)) as branch:
        with b.if_(IsSet(st)) as inner:
            b.emit(ir.SetBit(p, False))
            with inner.otherwise():
                b.emit(ir.SetBit(st, True))
        with branch.otherwise():
            b.emit(ir.SetBit(st, False))


@lowers("OSF")
def one_shot_falling(b: Builder, el, p: ir.Bit) -> None:
    st = b.memory_bit("st")
    with b.if_(IsSet(p)) as branch:
        b.emit(ir.SetBit(st, True))
        b.emit(ir.SetBit(p, False))
        with branch.otherwise(), b.if_(IsSet(st)):
            b.emit(ir.SetBit(st, False))
            b.emit(ir.SetBit(p, True))


@lowers("ODR")
def one_drop_rising(b: Builder, el, p: ir.Bit) -> None:
    st = b.memory_bit("st")
    with b.if_(IsSet(p)) as branch:
        with b.if_(IsSet(st, False)):
            b.emit(ir.SetBit(p, False))
            b.emit(ir.SetBit(st, True))
        with branch.otherwise():
            b.emit(ir.SetBit(p, True))
            b.emit(ir.SetBit(st, False))


@lowers("ODF")
def one_drop_falling(b: Builder, el, p: ir.Bit) -> None:
    st, hi = b.memory_bit("st"), b.memory_bit("hi")
    with b.if_(IsSet(p, False)) as branch:
        b.emit(ir.CopyBit(p, st))
        with b.if_(IsSet(hi)):
            b.emit(ir.SetBit(st, True))
        with branch.otherwise():
            b.emit(ir.SetBit(st, False))
            b.emit(ir.SetBit(hi, True))


@lowers("OSC")
def oscillator(b: Builder, el, p: ir.Bit) -> None:
    st = b.memory_bit("st")
    with b.if_(IsSet(p)) as branch:
        with b.if_(IsSet(st)) as inner:
            b.emit(ir.SetBit(st, False))
            b.emit(ir.SetBit(p, False))
            with inner.otherwise():
                b.emit(ir.SetBit(st, True))
        with branch.otherwise():
            b.emit(ir.SetBit(st, False))


@lowers(*RELATIONS)
def compare(b: Builder, el, p: ir.Bit) -> None:
    a, c = b.operand(el.args["op1"]), b.operand(el.args["op2"])
    with b.if_(IsSet(p)), b.if_(Holds(a, ir.NEGATED[RELATIONS[el.kind]], c)):
        b.emit(ir.SetBit(p, False))


@lowers("IF_BIT_SET", "IF_BIT_CLEAR")
def if_bit(b: Builder, el, p: ir.Bit) -> None:
    value = b.operand(el.args["var"])
    index = b.operand(el.args["bit"])
    wanted = el.kind == "IF_BIT_SET"
    with b.if_(IsSet(p)), b.if_(ir.BitOf(value, index, not wanted)):
        b.emit(ir.SetBit(p, False))


@lowers("SHORT", "LABEL", "COMMENT")
def pass_through(b: Builder, el, p: ir.Bit) -> None:
    """A wire, a jump target, a comment: no code."""


@lowers("OPEN")
def open_circuit(b: Builder, el, p: ir.Bit) -> None:
    b.emit(ir.SetBit(p, False))


@lowers("MASTER_RELAY")
def master_relay(b: Builder, el, p: ir.Bit) -> None:
    mcr = b.bit("$mcr")
    # a cleared relay is always set again here, or nothing could set it
    with b.if_(IsSet(mcr, False)) as branch:
        b.emit(ir.SetBit(mcr, True))
        with branch.otherwise():
            b.emit(ir.CopyBit(mcr, p))


def _when_powered(b: Builder, p: ir.Bit, op: ir.Op) -> None:
    with b.if_(IsSet(p)):
        b.emit(op)


@lowers("CLRWDT")
def clear_watchdog(b: Builder, el, p: ir.Bit) -> None:
    _when_powered(b, p, ir.ClearWatchdog())


@lowers("LOCK")
def lock(b: Builder, el, p: ir.Bit) -> None:
    _when_powered(b, p, ir.Halt())


@lowers("SLEEP")
def sleep(b: Builder, el, p: ir.Bit) -> None:
    _when_powered(b, p, ir.Sleep())


@lowers("DELAY")
def delay(b: Builder, el, p: ir.Bit) -> None:
    amount = str(el.args["delay"])
    if is_literal(amount):
        _when_powered(b, p, ir.Delay(ir.Const(b.literal(amount)), loops=False))
    else:
        _when_powered(b, p, ir.Delay(b.var(amount), loops=True))


@lowers("GOTO")
def goto(b: PartBuilder, el, p: ir.Bit) -> None:
    _when_powered(b, p, ir.Jump(b.jumps.goto_target(el)))


@lowers("GOSUB")
def gosub(b: PartBuilder, el, p: ir.Bit) -> None:
    _when_powered(b, p, ir.Call(b.jumps.gosub_target(el)))


@lowers("RETURN")
def return_(b: Builder, el, p: ir.Bit) -> None:
    _when_powered(b, p, ir.Return())


@lowers("ENDSUB")
def endsub(b: Builder, el, p: ir.Bit) -> None:
    b.emit(ir.Return())


@lowers("SUBPROG")
def subprog(b: PartBuilder, el, p: ir.Bit) -> None:
    # the normal flow of the scan skips the subroutine's body
    b.emit(ir.Jump(b.jumps.after_endsub(el)))
