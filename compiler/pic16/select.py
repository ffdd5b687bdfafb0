"""Instruction selection: each intermediate op, by its class, to the pattern
that writes its PIC16 code (bits.py, integers.py and peripherals.py hold
the patterns, which call the subroutines of routines.py by name; the few that
fit in a line are here)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from lang.semantics import ir

from ..analysis import loop_labels
from ..image import LoopBound
from . import bits, integers, peripherals
from .emit import Emitter, W
from .memory import FileBit, Layout
from .part import Part

if TYPE_CHECKING:
    from ..backend import Machine


@dataclass
class Context:
    e: Emitter
    part: Part
    layout: Layout
    machine: Machine
    delay_loop_cycles: int = peripherals.DELAY_LOOP_CYCLES  # clock cycles of one pass of DELAY's loop
    loops: set[str] = field(default_factory=set)  # labels reached by backward jumps or calls
    routines: set[str] = field(default_factory=set)
    tables: dict[bytes, str] = field(default_factory=dict)

    def bit(self, bit: ir.Bit) -> FileBit:
        return self.layout.bits[bit.name]

    def routine(self, name: str) -> str:
        self.routines.add(name)
        return name

    def table(self, data: bytes) -> str:
        """The label of a routine returning data[A1:A0] in W (one per distinct table)."""
        return self.tables.setdefault(data, f"table{len(self.tables) + 1}")

    def relative_table(self, entries: int) -> bool:
        """A table of this many entries is reached by BRW (PC + 1 + W, whatever
        PCLATH holds) from A0 alone: the enhanced core's, up to 256 entries."""
        return self.e.asm.relative_tables and entries <= 256


def _call(cx: Context, op: ir.Call) -> None:
    cx.e.call(op.target)


def _return(cx: Context, op: ir.Return) -> None:
    cx.e.ins("return")
    cx.e.end_path()


def _halt(cx: Context, op: ir.Halt) -> None:
    """An endless loop; LOCK never clears the watchdog, so an enabled
    watchdog resets the MCU as it does on LDmicro's code."""
    top = cx.e.new_label("lock")
    cx.e.label(top, loop=True, bound=LoopBound(None, "LOCK"))
    cx.e.goto(top)
    cx.e.end_path()


def _sleep(cx: Context, op: ir.Sleep) -> None:
    """SLEEP as LDmicro's PIC code has it. On the baseline (no INTCON: the
    PIC10F20x) a change on GP0, GP1 or GP3 from the level GPIO read last
    wakes the part with a reset, so the port is read just before SLEEP and
    nothing follows it (the program starts again; OPTION enables the wake-up,
    compiler/pic10/runtime.py). Elsewhere the external interrupt pin (RB0/INT,
    GP2/INT; INT0 on the PIC18) enabled as the wake-up source with the global
    enable off, so an edge on it wakes the MCU without a jump to the interrupt
    vector and the scan goes on after SLEEP; a watchdog time-out (TO cleared)
    sends it back to sleep."""
    e, part = cx.e, cx.part
    if not part.has("INTCON"):
        e.ins("movf", part.port("P"), W)
        e.label(e.new_label("sleep"), loop=True, bound=LoopBound(None, "SLEEP until a pin change resets the MCU"))
        e.ins("sleep")
        e.end_path()
        return
    intcon = part.bits("INTCON")
    enable, flag = intcon.get("INTE", intcon.get("INT0IE")), intcon.get("INTF", intcon.get("INT0IF"))
    assert enable is not None and flag is not None  # SLEEP is offered only on parts with an INT pin
    status = "STATUS" if "NOT_TO" in part.bits("STATUS") else "RCON"
    top = e.new_label("sleep")
    e.label(top, loop=True, bound=LoopBound(None, "SLEEP until the INT pin wakes the MCU"))
    e.ins("bcf", part.reg("INTCON"), intcon["GIE"])
    e.ins("bcf", part.reg("INTCON"), flag)
    e.ins("bsf", part.reg("INTCON"), enable)
    e.ins("sleep")
    e.ins("nop")  # the instruction fetched before the wake-up
    e.ins("btfss", part.reg(status), part.bit(status, "NOT_TO"))
    e.goto(top)


def _delay(cx: Context, op: ir.Delay) -> None:
    peripherals.delay(cx, op)


PATTERNS = {
    ir.Label: lambda cx, op: cx.e.label(op.name, loop=op.name in cx.loops),
    ir.Note: lambda cx, op: cx.e.comment(op.text),
    ir.Jump: lambda cx, op: cx.e.goto(op.target),
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
    ir.UartReady: peripherals.uart_ready,
    ir.UartAvailable: peripherals.uart_available,
    ir.UartTake: peripherals.uart_take,
    ir.EepromLoad: peripherals.eeprom_load,
    ir.EepromSave: peripherals.eeprom_save,
    ir.Delay: _delay,
    ir.ClearWatchdog: lambda cx, op: cx.e.ins("clrwdt"),
    ir.Halt: _halt,
    ir.Sleep: _sleep,
}


def select(cx: Context, ops: list[ir.Op]) -> None:
    for op in ops:
        PATTERNS[type(op)](cx, op)


def prepare(cx: Context, code: ir.Code) -> None:
    cx.loops = loop_labels(code.scan)
