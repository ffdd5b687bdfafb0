"""The AVR back end: intermediate code and a Machine to a flash image and
its listing (GNU avr-as source). Registers itself with `compiler.backend`."""

from __future__ import annotations

from lang.hardware import baud_setting
from lang.semantics import ir

from ..analysis import loop_labels, uses_uart
from ..backend import Machine, register
from ..errors import FLASH_FULL, RAM_FULL, fail
from ..image import Image, Symbol
from . import flow as avr_flow
from . import stack
from .asm import Assembler, Data, Label, compress_skips
from .emit import Emitter
from .memory import RegBit, allocate, fits_ram
from .part import Part
from .peripherals import UART_IDLE
from .routines import write_routines
from .runtime import cycle_variables, scan_limit, write_runtime
from .select import DELAY_LOOP_CYCLES, Context


class AvrBackend:
    family = "avr"
    delay_loop_cycles = DELAY_LOOP_CYCLES
    rungs_by_jumps = False
    flow = avr_flow

    def compile(self, code: ir.Code, machine: Machine) -> Image:
        part = Part.of(machine.device)
        if uses_uart(code):
            code.bits[UART_IDLE] = ir.MEMORY
        code.vars.update(cycle_variables(part))
        layout = allocate(code, part, machine)
        assembler = Assembler(part.long_jumps, part.flash // 2, part.core)
        cx = Context(Emitter(assembler), part, layout, machine.crystal_hz, machine.baud)
        if uses_uart(code):
            cx.uart_double = bool(baud_setting(machine.device, machine.crystal_hz, machine.baud).select)
        cx.loops = loop_labels(code.scan)
        cx.e.jump("start")
        cx.e.label("start", loop=True)
        write_runtime(cx, code, machine)
        write_routines(cx.e, cx.routines)
        # tables right after the first jump: LPM reaches the first 64 KB
        tables = [item for data, name in cx.tables.items() for item in (Label(name), Data(data))]
        assembler.items[1:1] = tables
        if not tables:
            del assembler.items[0]  # the jump over them
        compress_skips(assembler.items)
        assembled = assembler.assemble()
        if 2 * len(assembled.words) > part.flash:
            raise fail(FLASH_FULL, f"the program needs {2 * len(assembled.words)} bytes of flash; the "
                                   f"{part.title} has {part.flash}")
        if part.measures_stack:
            deepest = stack.depth(assembled.words, machine.device)
            if deepest is None:
                raise fail(RAM_FULL, f"the stack has no bound (a subroutine that calls itself); the {part.title} "
                                     f"has {part.avr['ram']['size']} bytes of RAM")
            fits_ram(part, layout.ram_used, deepest)
        header = (f"; {part.title} ({part.mmcu}): {2 * len(assembled.words)} bytes of flash, "
                  f"{layout.ram_used} bytes of RAM\n"
                  f"; reassemble: avr-gcc -mmcu={part.mmcu} -nostdlib -nostartfiles -x assembler FILE -o prog.elf"
                  f" && avr-objcopy -O ihex prog.elf prog.hex\n")
        return Image(words=assembled.words, listing=header + assembled.listing, ram_bytes=layout.ram_used,
                     ram_size=part.avr["ram"]["size"], flash_size=part.flash, flash_unit="bytes",
                     warnings=[], symbols=_symbols(layout), labels=assembled.symbols,
                     loops=dict(cx.e.bounds), scan_limit=scan_limit(part, machine))


def _symbols(layout) -> dict[str, Symbol]:
    found = {name: Symbol(loc.reg, 1, loc.bit) if isinstance(loc, RegBit) else Symbol(loc.addr, 1, loc.bit)
             for name, loc in layout.bits.items()}
    found.update((name, Symbol(st.addr, st.size)) for name, st in layout.vars.items())
    return found


register(AvrBackend())
