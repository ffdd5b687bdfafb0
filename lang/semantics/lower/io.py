"""Peripheral instructions: ADC, PWM, PERSIST and the UART elements with
formatted strings (lang/strings.py reads the format). The simulator's
peripheral objects, or the part's hardware, do the rest."""

from __future__ import annotations

from contextlib import ExitStack
from typing import TYPE_CHECKING

from lang.numbers import byte_needed
from lang.storage import eeprom_refusal
from lang.strings import parse_format

from .. import ir
from ..errors import EEPROM, OPERAND, fail
from ..operands import PWM_FULL
from .builder import Builder, Holds, IsSet, lowers

if TYPE_CHECKING:
    from . import PartBuilder


@lowers("READ_ADC")
def read_adc(b: PartBuilder, el, p: ir.Bit) -> None:
    d = b.dest("name")
    with b.if_(IsSet(p)):
        b.emit(ir.ReadAdc(d, b.adc_channel(d.name), int(el.args.get("refs") or 0)))


@lowers("SET_PWM")
def set_pwm(b: PartBuilder, el, p: ir.Bit) -> None:
    name = el.args["name"]
    resolution = str(el.args.get("resolution") or "0-100%")
    with b.if_(IsSet(p)):
        b.emit(ir.SetPwm(b.pwm_unit(name), b.operand(el.args["duty"]), PWM_FULL[resolution],
                         int(el.args["freq"])))
        b.emit(ir.SetBit(b.bit(name), True))


@lowers("PERSIST")
def persist(b: Builder, el, p: ir.Bit) -> None:
    v = b.dest("var")
    address, b.eeprom = b.eeprom_places[id(el)]
    refused = eeprom_refusal(b.eeprom, b.eeprom_size)
    if refused:
        raise fail(EEPROM, refused, el)
    loaded = b.memory_bit("loaded")
    with b.if_(IsSet(p)):
        # the first powered scan loads the variable from EEPROM; later ones
        # write it back whenever it differs from the EEPROM copy
        with b.if_(IsSet(loaded, False)) as branch:
            b.emit(ir.SetBit(loaded, True))
            b.emit(ir.EepromLoad(v, address))
            with branch.otherwise():
                b.emit(ir.EepromSave(v, address))


def byte_of(value: ir.Var | ir.Const, index: int) -> ir.Operand:
    """Byte `index` (0 = least significant) of a variable or a constant, unsigned."""
    if isinstance(value, ir.Const):
        return ir.Const((value.value >> 8 * index) & 0xFF)
    return ir.Byte(value, index)


def _busy(b: Builder, p: ir.Bit) -> None:
    b.emit(ir.UartReady(p))
    b.emit(ir.CopyBit(p, p, True))


@lowers("UART_SEND")
def uart_send(b: Builder, el, p: ir.Bit) -> None:
    value = b.operand(el.args["var"])
    count = int(el.args.get("bytes", 1) or 1)
    if count == 1:
        with b.if_(IsSet(p)):
            b.emit(ir.UartSend(byte_of(value, 0)))
    elif el.args.get("wait"):
        # all bytes in this scan, the MCU waiting for each (low byte first)
        with b.if_(IsSet(p)):
            for i in range(count):
                b.emit(ir.UartSend(byte_of(value, i), wait=True))
    else:
        # one byte per scan from a copy taken when sending starts
        active, saved, sent = b.memory_bit("active"), b.memory_var("saved"), b.memory_var("sent", 1)
        with b.if_(IsSet(p)), b.if_(IsSet(active, False)):
            b.emit(ir.SetBit(active, True))
            b.emit(ir.Move(saved, value))
            b.emit(ir.Move(sent, ir.Const(0)))
        with b.if_(IsSet(active)):
            ready = b.temp()
            b.emit(ir.UartReady(ready))
            with b.if_(IsSet(ready)):
                for i in range(count):
                    with b.if_(Holds(sent, "==", ir.Const(i))):
                        b.emit(ir.UartSend(ir.Byte(saved, i)))
                with b.if_(Holds(sent, "<", ir.Const(count))):
                    b.emit(ir.Arith("add", sent, sent, ir.Const(1)))
            with b.if_(Holds(sent, ">=", ir.Const(count))):
                b.emit(ir.SetBit(active, False))
        with b.if_(IsSet(active)) as branch:
            b.emit(ir.SetBit(p, True))
            with branch.otherwise():
                _busy(b, p)
        return
    # the rung's output is the transmitter's busy flag, whatever the input
    _busy(b, p)


@lowers("UART_RECV")
def uart_recv(b: Builder, el, p: ir.Bit) -> None:
    d = b.dest("var")
    count = int(el.args.get("bytes", 1) or 1)
    if count == 1:
        with b.if_(IsSet(p)):
            b.emit(ir.UartAvailable(p))
            with b.if_(IsSet(p)):
                b.emit(ir.UartTake(d))
    elif el.args.get("wait"):
        received = b.temp_var()
        with b.if_(IsSet(p)):
            b.emit(ir.UartAvailable(p))
            with b.if_(IsSet(p)):
                b.emit(ir.Move(received, ir.Const(0)))
                for i in range(count):
                    b.emit(ir.UartTake(ir.Byte(received, i), wait=i > 0))
                b.emit(ir.Move(d, received))
    else:
        saved, got = b.memory_var("saved"), b.memory_var("got", 1)
        with b.if_(IsSet(p)):
            available = b.temp()
            b.emit(ir.UartAvailable(available))
            with b.if_(IsSet(available)):
                with b.if_(Holds(got, "<", ir.Const(count))):
                    for i in range(count):
                        with b.if_(Holds(got, "==", ir.Const(i))):
                            b.emit(ir.UartTake(ir.Byte(saved, i)))
                    b.emit(ir.Arith("add", got, got, ir.Const(1)))
            with b.if_(Holds(got, ">=", ir.Const(count))) as branch:
                b.emit(ir.Move(d, saved))
                b.emit(ir.Move(got, ir.Const(0)))
                b.emit(ir.SetBit(p, True))
                with branch.otherwise():
                    b.emit(ir.SetBit(p, False))


@lowers("UART_SEND_READY")
def uart_send_ready(b: Builder, el, p: ir.Bit) -> None:
    with b.if_(IsSet(p)):
        b.emit(ir.UartReady(p))


@lowers("UART_RECV_AVAIL")
def uart_recv_avail(b: Builder, el, p: ir.Bit) -> None:
    with b.if_(IsSet(p)):
        b.emit(ir.UartAvailable(p))


@lowers("FORMATTED_STRING")
def formatted_string(b: Builder, el, p: ir.Bit) -> None:
    try:
        fmt = parse_format(str(el.args.get("text") or ""))
    except ValueError as bad:
        raise fail(OPERAND, str(bad), el) from None
    name = str(el.args.get("var") or "")
    if fmt.digits and not name:
        raise fail(OPERAND, "a variable is interpolated into the formatted string, but none is specified", el)
    # a variable the text never inserts is not read (LD323 warns), as in LDmicro's code
    value = b.operand(name) if name and fmt.digits else ir.Const(0)
    steps, count = fmt.steps, len(fmt.steps)
    one, busy, lead = b.memory_bit("one"), b.memory_bit("busy"), b.memory_bit("lead")
    seq, conv = b.memory_var("seq", 1 if count < 128 else 2), b.memory_var("conv")
    byte, quotient = b.temp_var(1), b.temp_var()
    with b.if_(IsSet(p)) as branch:
        with b.if_(IsSet(one, False)):
            b.emit(ir.SetBit(one, True))
            b.emit(ir.Move(seq, ir.Const(0)))
            b.emit(ir.SetBit(busy, True))
        with branch.otherwise():
            b.emit(ir.SetBit(one, False))
    ready = b.temp()
    with b.if_(IsSet(busy)):
        with b.if_(Holds(seq, "<", ir.Const(count))):
            b.emit(ir.UartReady(ready))
            with b.if_(IsSet(ready)):
                # the byte of a sign or digit position is computed, any
                # other is the text's character, from a table
                with ExitStack() as chain:
                    for position, (kind, arg) in enumerate(steps):
                        if kind == "c":
                            continue
                        branch = chain.enter_context(b.if_(Holds(seq, "==", ir.Const(position))))
                        if kind == "s":
                            _sign(b, value, conv, byte)
                        else:
                            _digit(b, fmt, arg, value, conv, byte, quotient, lead)
                        chain.enter_context(branch.otherwise())
                    b.emit(ir.Table(byte, tuple(arg if kind == "c" else 0 for kind, arg in steps), seq))
                b.emit(ir.UartSend(byte))
                b.emit(ir.Arith("add", seq, seq, ir.Const(1)))
    with b.if_(Holds(seq, "<", ir.Const(count))) as branch:
        b.emit(ir.CopyBit(p, busy))
        with branch.otherwise():
            b.emit(ir.SetBit(p, False))
            b.emit(ir.SetBit(busy, False))


def _sign(b: Builder, value, conv, byte) -> None:
    """The sign position also loads the absolute value to convert."""
    with b.if_(Holds(value, "<", ir.Const(0))) as branch:
        b.emit(ir.Move(byte, ir.Const(ord("-"))))
        b.emit(ir.Unary("neg", conv, value))
        with branch.otherwise():
            b.emit(ir.Move(byte, ir.Const(ord(" "))))
            b.emit(ir.Move(conv, value))


def _digit(b: Builder, fmt, index: int, value, conv, byte, quotient, lead) -> None:
    if index == 0:
        if not fmt.signed:
            b.emit(ir.Move(conv, value))
        b.emit(ir.SetBit(lead, True))
    scale = ir.Const(10 ** (fmt.digits - index - 1))
    b.emit(ir.Divide("div", quotient, conv, scale, remainder=conv))
    b.emit(ir.Arith("add", byte, quotient, ir.Const(ord("0"))))
    if index != fmt.digits - 1:
        # all but the last digit: leading zeros become blanks
        with b.if_(Holds(byte, "==", ir.Const(ord("0")))) as branch:
            with b.if_(IsSet(lead)):
                b.emit(ir.Move(byte, ir.Const(ord(" "))))
            with branch.otherwise():
                b.emit(ir.SetBit(lead, False))


# LDmicro's QUAD_ENCOD (intcode.cpp, QUAD_ALGO 2): the last two samples of A
# and B index a table of counts, one count for two of the four edges of a
# cycle; the direction decides its sign
QUAD_STEPS = (0, 0, 1, 0, 0, 0, 0, -1, -1, 0, 0, 0, 0, 1, 0, 0)


@lowers("QUAD_ENCOD")
def quad_encoder(b: Builder, el, p: ir.Bit) -> None:
    """While powered: a count (the output pulses for the scan), the direction
    output set counting up and cleared counting down; the Z input's edge
    (zkind) passes power and zeroes the counter, or with `counts` per
    revolution rounds it to whole revolutions. LDmicro keeps the state per
    counter name and the Z memory per Z input name: so do these names."""
    counter = b.dest("counter")
    state, step = ir.Var(f"$state_{counter.name}", 1), ir.Var(f"$dir_{counter.name}", 1)
    b.vars[state.name] = b.vars[step.name] = 1
    counts = int(el.args.get("counts") or 0)
    ticks = ir.Var(f"$ticks_{counter.name}", byte_needed(counts))
    revolutions = ir.Var(f"$revol_{counter.name}", counter.size)
    direction = str(el.args.get("dir") or "")
    with b.if_(IsSet(p)):
        b.emit(ir.SetBit(p, False))
        b.emit(ir.Shift("shl", state, state, ir.Const(2), 1))
        b.emit(ir.Arith("and", state, state, ir.Const(0x0F)))
        for bit, name in ((0, el.args["a"]), (1, el.args["b"])):
            with b.if_(IsSet(b.bit(str(name)))):
                b.emit(ir.ChangeBitOf(state, ir.Const(bit), True))
        b.emit(ir.Table(step, QUAD_STEPS, state))
        for rel, change, level in ((">", "add", True), ("<", "sub", False)):
            with b.if_(Holds(step, rel, ir.Const(0))):
                b.emit(ir.Arith(change, counter, counter, ir.Const(1)))
                if counts > 0:
                    b.vars[ticks.name] = ticks.size
                    b.emit(ir.Arith(change, ticks, ticks, ir.Const(1)))
                if direction:
                    b.emit(ir.SetBit(b.bit(direction), level))
                b.emit(ir.SetBit(p, True))
        if el.args.get("z"):
            _quad_index(b, el, p, counter, counts, ticks, revolutions)


def _quad_index(b: Builder, el, p: ir.Bit, counter: ir.Var, counts: int, ticks: ir.Var, revolutions: ir.Var) -> None:
    z = b.bit(str(el.args["z"]))
    now, before, pulse = b.temp(), b.bit(f"$prev_{z.name}"), b.bit(f"$quad_{counter.name}")
    kind = str(el.args.get("zkind") or "/")
    b.emit(ir.CopyBit(now, z))
    if kind in "/\\":
        b.emit(ir.CopyBit(pulse, now, invert=kind == "\\"))
        b.emit(ir.AndBit(pulse, before, invert=kind == "/"))
    else:
        b.emit(ir.CopyBit(pulse, z, invert=kind == "o"))
    b.emit(ir.CopyBit(before, now))
    with b.if_(IsSet(pulse)):
        b.emit(ir.SetBit(p, True))
        if counts == 0:
            b.emit(ir.Move(counter, ir.Const(0)))
        elif counts > 0:
            b.vars[revolutions.name] = revolutions.size
            # C's division: -counts / 2 is truncated toward zero as counts / 2 is
            for rel, limit, change in ((">", counts // 2, "add"), ("<", -(counts // 2), "sub")):
                with b.if_(Holds(ticks, rel, ir.Const(limit))):
                    b.emit(ir.Arith(change, revolutions, revolutions, ir.Const(1)))
                    b.emit(ir.Arith("mul", counter, revolutions, ir.Const(counts)))
                    b.emit(ir.Move(ticks, ir.Const(0)))
