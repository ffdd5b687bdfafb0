"""The AVR back end: intermediate code to a flash image and its listing."""

from __future__ import annotations

from dataclasses import dataclass

from lang.diagnostics import Diagnostic
from lang.model import Program

from .. import ir
from ..errors import FLASH_FULL, fail
from .asm import Assembler, Data, Label, compress_skips
from .emit import Emitter
from .memory import RegBit, allocate
from .part import Part
from .peripherals import UART_IDLE, baud_divisor, check_pwm
from .routines import write_routines
from .runtime import write_runtime
from .select import Context, loop_labels


@dataclass(frozen=True)
class Symbol:
    """Where a name lives in the data space (registers are addresses 0..31)."""

    address: int
    size: int  # bytes, 1 for a bit
    bit: int | None = None


@dataclass
class Image:
    part: Part
    words: list[int]
    listing: str
    ram_bytes: int
    warnings: list[Diagnostic]
    symbols: dict[str, Symbol]
    labels: dict[str, int]  # listing label -> word address


def _uses_uart(code: ir.Code) -> bool:
    return any(isinstance(op, (ir.UartSend, ir.UartReady, ir.UartAvailable, ir.UartTake)) for op in code.scan)


def compile_avr(code: ir.Code, part: Part, program: Program, pwm_elements: dict) -> Image:
    settings = program.settings
    if _uses_uart(code):
        code.bits[UART_IDLE] = ir.MEMORY
    layout = allocate(code, part, program)
    assembler = Assembler(part.long_jumps, part.flash // 2)
    cx = Context(Emitter(assembler), part, layout, settings.crystal_hz, settings.baud)
    if _uses_uart(code):
        cx.uart_double = baud_divisor(settings.crystal_hz, settings.baud)[1]
    warnings = check_pwm(cx, code.scan, pwm_elements)
    cx.loops = loop_labels(code.scan)
    cx.e.jump("start")
    cx.e.label("start", loop=True)
    write_runtime(cx, code, program)
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
    header = (f"; {part.title} ({part.mmcu}): {2 * len(assembled.words)} bytes of flash, "
              f"{layout.ram_used} bytes of RAM\n"
              f"; reassemble: avr-gcc -mmcu={part.mmcu} -nostdlib -nostartfiles -x assembler FILE -o prog.elf"
              f" && avr-objcopy -O ihex prog.elf prog.hex\n")
    return Image(part, assembled.words, header + assembled.listing, layout.ram_used, warnings, _symbols(layout),
                 assembled.symbols)


def _symbols(layout) -> dict[str, Symbol]:
    found = {name: Symbol(loc.reg, 1, loc.bit) if isinstance(loc, RegBit) else Symbol(loc.addr, 1, loc.bit)
             for name, loc in layout.bits.items()}
    found.update((name, Symbol(st.addr, st.size)) for name, st in layout.vars.items())
    return found

