"""Instruction selection: each intermediate op, by its class, to the pattern
that writes its AVR code (bits.py, integers.py, peripherals.py hold the
patterns; the few that fit in a line are here)."""

from __future__ import annotations

from dataclasses import dataclass, field

from lang.semantics import ir

from ..image import LoopBound
from . import bits, integers, peripherals, sfr
from .emit import SCRATCH, A, Emitter
from .memory import Layout, RegBit
from .part import Part
from .routines import WITHOUT_MUL

DELAY_LOOP_CYCLES = 8  # the loop below: WDR, NOP, SUBI, 3 x SBCI, BRNE taken

@dataclass
class Context:
    e: Emitter
    part: Part
    layout: Layout
    crystal_hz: int
    baud: int
    uart_double: bool = False
    loops: set[str] = field(default_factory=set)  # labels reached by backward jumps or calls
    routines: set[str] = field(default_factory=set)
    tables: dict[bytes, str] = field(default_factory=dict)

    def bit(self, bit: ir.Bit):
        return self.layout.bits[bit.name]

    def routine(self, name: str) -> str:
        if not self.part.has_mul:
            name = WITHOUT_MUL.get(name, name)
        self.routines.add(name)
        return name

    def table(self, data: bytes) -> str:
        """A label for the bytes in flash (one copy per distinct table)."""
        return self.tables.setdefault(data, f"table{len(self.tables) + 1}")


def _call(cx: Context, op: ir.Call) -> None:
    # the temporaries still needed after the call live in r16/r17, which the
    # called rungs use too
    saved = sorted({cx.bit(b).reg for b in op.keep if isinstance(cx.bit(b), RegBit)})
    for reg in saved:
        cx.e.ins("push", reg)
    cx.e.call(op.target)
    for reg in reversed(saved):
        cx.e.ins("pop", reg)
    cx.e.forget_scratch()


def _return(cx: Context, op: ir.Return) -> None:
    cx.e.ins("ret")
    cx.e.end_path()


def _halt(cx: Context, op: ir.Halt) -> None:
    """An endless loop: the watchdog resets the MCU."""
    top = cx.e.new_label()
    cx.e.label(top, loop=True, bound=LoopBound(None, "LOCK"))
    cx.e.jump(top)


def _sleep(cx: Context, op: ir.Sleep) -> None:
    sleep = cx.part.avr["sleep"]
    cx.e.store_byte(cx.part.reg(sleep["control"]), cx.e.constant_reg(sleep["power_down"]), False)
    cx.e.ins("sleep")


def _delay(cx: Context, op: ir.Delay) -> None:
    """A loop of DELAY_LOOP_CYCLES cycles per count, clearing the watchdog."""
    e = cx.e
    done, top = e.new_label(), e.new_label()
    if op.loops:
        integers.load(cx, op.amount, A)
        e.ins("tst", A[3])
        e.branch("brmi", done)
        bound = LoopBound(None, "a DELAY by a variable")
    else:
        assert isinstance(op.amount, ir.Const)  # a delay that does not loop is a constant time
        count = round(op.amount.value * cx.crystal_hz / (1_000_000 * DELAY_LOOP_CYCLES))
        if not count:
            return
        integers.load(cx, ir.Const(count), A)
        bound = LoopBound(count, "DELAY")
    e.ins("mov", SCRATCH, A[0])
    for reg in A[1:]:
        e.ins("or_", SCRATCH, reg)
    e.branch("breq", done)
    e.label(top, loop=True, bound=bound)
    e.ins("wdr")
    e.ins("nop")
    e.ins("subi", A[0], 1)
    for reg in A[1:]:
        e.ins("sbci", reg, 0)
    e.branch("brne", top)
    e.label(done)


PATTERNS = {
    ir.Label: lambda cx, op: cx.e.label(op.name, loop=op.name in cx.loops),
    ir.Note: lambda cx, op: cx.e.comment(op.text),
    ir.Jump: lambda cx, op: cx.e.jump(op.target),
    ir.JumpIfBit: lambda cx, op: bits.jump_if(cx.e, cx.bit(op.bit), op.value, op.target),
    ir.JumpIf: integers.compare_jump,
    ir.JumpIfBitOf: integers.jump_if_bit_of,
    ir.Call: _call,
    ir.Return: _return,
    ir.SetBit: lambda cx, op: bits.write(cx.e, cx.bit(op.dst), op.value),
    ir.CopyBit: lambda cx, op: bits.copy(cx.e, cx.bit(op.dst), cx.bit(op.src), op.invert),
    ir.AndBit: lambda cx, op: bits.and_(cx.e, cx.bit(op.dst), cx.bit(op.src), op.invert),
    ir.OrBit: lambda cx, op: bits.or_(cx.e, cx.bit(op.dst), cx.bit(op.src)),
    ir.Move: integers.move,
    ir.Arith: integers.arith,
    ir.ChangeBitOf: integers.change_bit,
    ir.Divide: integers.divide,
    ir.Unary: integers.unary,
    ir.Shift: integers.shift,
    ir.Convert: integers.convert,
    ir.Table: integers.table,
    ir.Permute: integers.permute,
    ir.ReadAdc: peripherals.read_adc,
    ir.SetPwm: peripherals.set_pwm,
    ir.PwmOff: peripherals.pwm_off,
    ir.UartSend: peripherals.uart_send,
    ir.UartReady: lambda cx, op: peripherals.uart_ready(cx, op.dst),
    ir.UartAvailable: lambda cx, op: peripherals.uart_available(cx, op.dst),
    ir.UartTake: peripherals.uart_take,
    ir.ReadSfr: sfr.read_sfr,
    ir.WriteSfr: sfr.write_sfr,
    ir.EepromLoad: peripherals.eeprom_load,
    ir.EepromSave: peripherals.eeprom_save,
    ir.Delay: _delay,
    ir.ClearWatchdog: lambda cx, op: cx.e.ins("wdr"),
    ir.Halt: _halt,
    ir.Sleep: _sleep,
}


def select(cx: Context, ops: list[ir.Op]) -> None:
    for op in ops:
        PATTERNS[type(op)](cx, op)

