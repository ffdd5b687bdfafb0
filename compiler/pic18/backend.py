"""The PIC18 back end: intermediate code to a program-memory image, the
configuration bytes and a gpasm listing.

The instruction patterns, the runtime and the routines are the PIC16 back
end's (compiler/pic16/): they write mid-range instructions, which the PIC18
runs as its own (the same byte, bit and literal operations with the same
flags, RLF and RRF as RLCF and RRCF), through the shared emitter with the
PIC18's `Core` (BSR and the access bank). What is the PIC18's own: the
encoder and assembler (conditional branches for the flag tests, one-word
BRA/RCALL, two-word GOTO/CALL, no pages),
the multiply on the hardware multiplier, tables read with TBLRD, the memory
map and the configuration bytes.
"""

from __future__ import annotations

from lang.hardware import clock_refusal
from lang.semantics import ir

from ..errors import FLASH_FULL, INTERNAL_CLOCK, fail
from ..image import Image
from ..pic16.asm import ProgramTooLarge
from ..pic16.backend import ram_in_use, symbols
from ..pic16.emit import Emitter, compress_skips
from ..pic16.memory import allocate
from ..pic16.peripherals import DELAY_LOOP_CYCLES
from ..pic16.routines import write_routines
from ..pic16.runtime import free_running, write_runtime
from ..pic16.select import Context, prepare
from . import flow as pic18_flow
from .asm import Assembler
from .core import Pic18Core
from .part import Part
from .routines import hardware_multiply


def _write_tables(cx: Context) -> None:
    """Each table: a routine returning data[A1:A0] in W, read from program
    memory by TBLRD at the table's byte address plus the index."""
    e, s, part = cx.e, cx.layout.scratch, cx.part
    for data, name in cx.tables.items():
        entries = f"{name}_data"
        e.label(name, loop=True)
        e.asm.address(entries, high=False)
        e.forget_w()
        e.ins("addwf", s[0], 0)
        e.store(part.reg("TBLPTRL"))
        e.asm.address(entries, high=True)
        e.forget_w()
        e.ins("addwfc", s[1], 0)
        e.store(part.reg("TBLPTRH"))
        e.ins("clrf", part.reg("TBLPTRU"))
        e.ins("tblrd*")
        e.load(part.reg("TABLAT"))
        e.ins("return")
        e.end_path()
        e.asm.table(entries, data)


class Pic18Backend:
    family = "pic18"
    # the PIC16's loop, whose closing test and jump are one BNZ here: 18 instruction cycles a count
    delay_loop_cycles = DELAY_LOOP_CYCLES - 4
    rungs_by_jumps = False
    flow = pic18_flow

    def compile(self, code: ir.Code, machine) -> Image:
        part = Part.of(machine.device)
        refusal = clock_refusal(part.device, machine.crystal_hz, machine.config_word)
        if refusal is not None:
            raise fail(INTERNAL_CLOCK, refusal)  # the checks say it first, on the header (LD716)
        layout = allocate(code, part, machine, free_running(code, part, machine))
        assembler = Assembler(part.flash_words, part.reg("STATUS"))
        cx = Context(Emitter(assembler, part, ram_in_use(layout), Pic18Core(part)), part, layout, machine,
                     self.delay_loop_cycles)
        prepare(cx, code)
        write_runtime(cx, code)
        write_routines(cx.e, layout.scratch, cx.routines, hardware_multiply(part))
        _write_tables(cx)
        compress_skips(assembler.items)
        config = part.config_bytes(machine.config_word, machine.crystal_hz)
        header = (f"; {part.title}: {{bytes}} bytes of program memory, {layout.ram_used} bytes of RAM\n"
                  f"; reassemble: gpasm -p {part.processor} FILE\n")
        crystal = part.pll_crystal(machine.crystal_hz) if machine.config_word is None else None
        if crystal is not None:
            header += (f"; clock {machine.crystal_hz / 1e6:g} MHz: HS oscillator with the PLL (x{part.feature('pll')['factor']}),"
                       f" a {crystal / 1e6:g} MHz crystal\n")
        try:
            assembled = assembler.assemble(processor=part.processor, config=config)
        except ProgramTooLarge as error:
            raise fail(FLASH_FULL, f"the program needs {2 * error.words} bytes of program memory; the "
                                   f"{part.title} has {2 * part.flash_words}") from None
        listing = header.format(bytes=2 * len(assembled.words)) + assembled.listing
        return Image(
            words=assembled.words, listing=listing, ram_bytes=layout.ram_used, ram_size=layout.ram_size,
            flash_size=2 * part.flash_words, flash_unit="bytes", warnings=[], symbols=symbols(layout),
            labels=assembled.symbols, segments={min(config): bytes(config[a] for a in sorted(config))},
            listing_suffix=".asm", loops=dict(cx.e.bounds))
