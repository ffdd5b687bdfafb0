"""Peripheral patterns: busy-wait delays; the A/D converter, PWM, UART and
data EEPROM are not compiled for PIC16 yet and are refused with a located
error (LD702) naming the instruction."""

from __future__ import annotations

from .. import ir
from ..image import LoopBound
from ..errors import NOT_COMPILED, fail
from . import integers as ints
from .emit import STATUS, W, Z

# one count of a variable DELAY: 19 instruction cycles of 4 clock cycles
DELAY_LOOP_CYCLES = 76


def delay(cx, op: ir.Delay) -> None:
    """A loop of DELAY_LOOP_CYCLES clock cycles per count, clearing the watchdog."""
    from .routines import Scratch

    e = cx.e
    s = Scratch(cx.layout.scratch)
    done = e.new_label("delay")
    if op.loops:
        ints.copy_in(cx, op.amount, s.A)
        e.ins("btfsc", s.A[3], 7)
        e.goto(done)  # a negative count waits nothing
    else:
        count = round(op.amount.value * cx.machine.crystal_hz / (1_000_000 * DELAY_LOOP_CYCLES))
        if count <= 0:
            return
        ints.copy_in(cx, ir.Const(count), s.A)
    e.load(s.A[0])
    for reg in s.A[1:]:
        e.ins("iorwf", reg, W)
    e.ins("btfsc", STATUS, Z)
    e.goto(done)
    top = e.new_label("delay")
    e.label(top, loop=True, bound=LoopBound(None if op.loops else count, "DELAY"))
    e.ins("clrwdt")
    ints.add_constant(e, s.A, -1)
    e.load(s.A[0])
    for reg in s.A[1:]:
        e.ins("iorwf", reg, W)
    e.ins("btfss", STATUS, Z)
    e.goto(top)
    e.label(done)


def _refused(what: str, kind: str):
    def pattern(cx, op) -> None:
        found = cx.machine.elements(kind)
        raise fail(NOT_COMPILED, f"{what} is not compiled for PIC16 yet", found[0] if found else None)
    return pattern


read_adc = _refused("READ ADC", "READ_ADC")
set_pwm = _refused("SET PWM", "SET_PWM")
pwm_off = _refused("SET PWM", "SET_PWM")
uart_send = _refused("UART output", "UART_SEND")
uart_ready = _refused("UART output", "UART_SEND")
uart_available = _refused("UART input", "UART_RECV")
uart_take = _refused("UART input", "UART_RECV")
eeprom_load = _refused("PERSIST", "PERSIST")
eeprom_save = _refused("PERSIST", "PERSIST")
