"""The PIC16 back end: intermediate code to a program-memory image, the
configuration word(s) and a gpasm listing."""

from __future__ import annotations

from collections.abc import Callable

from lang.semantics import ir

from ..errors import FLASH_FULL, fail
from ..image import Image, Symbol
from . import asm as a
from . import flow as pic16_flow
from .emit import Core, Emitter, MidRange, compress_skips
from .memory import allocate
from .part import Part
from .peripherals import DELAY_LOOP_CYCLES
from .routines import write_routines
from .runtime import free_running, write_runtime
from .select import Context, prepare


def ram_in_use(layout) -> frozenset[int]:
    used = set(layout.scratch)
    if layout.clock is not None:
        used.update(range(layout.clock, layout.clock + layout.clock_bytes))
    used.update(loc.addr for loc in layout.bits.values() if loc.ram)
    for st in layout.vars.values():
        if st.ram:
            used.update(range(st.addr, st.addr + st.size))
    return frozenset(used)


def _write_tables(cx: Context) -> None:
    """Each table: a routine that jumps to RETLW data[A1:A0] (PCLATH takes
    the high byte of the entry's address: the table may cross 256-word
    boundaries and pages), or BRW from A0 where the core has it
    (`Context.relative_table`)."""
    e, s = cx.e, cx.layout.scratch
    for data, name in cx.tables.items():
        entries = f"{name}_data"
        e.label(name, loop=True)
        if cx.relative_table(len(data)):
            e.ins("movf", s[0], 0)
            e.ins("brw")
            e.end_path()
            e.asm.table(entries, data)
            continue
        e.asm.address(entries, high=True)
        e.ins("movwf", 0x0A)
        e.ins("movf", s[1], 0)
        e.ins("addwf", 0x0A, 1)
        e.asm.address(entries, high=False)
        e.forget_w()
        e.ins("addwf", s[0], 0)
        e.ins("btfsc", 0x03, 0)
        e.ins("incf", 0x0A, 1)
        e.ins("movwf", 0x02)
        e.end_path()
        e.asm.table(entries, data)


class Pic16Backend:
    family = "pic16"
    delay_loop_cycles = DELAY_LOOP_CYCLES
    rungs_by_jumps = False
    flow = pic16_flow

    def __init__(self, enhanced: Callable[[ir.Code, object], Image]):
        self._enhanced = enhanced  # the enhanced mid-range core's back end (compiler/pic16/enhanced/)

    def compile(self, code: ir.Code, machine) -> Image:
        part = Part.of(machine.device)
        if part.enhanced:
            return self._enhanced(code, machine)
        layout = allocate(code, part, machine, free_running(code, part, machine))
        # the PIC12F675 keeps its oscillator calibration (a RETLW) in its last word
        reserved = 1 if part.feature("osccal") else 0
        ram = ram_in_use(layout)
        # banks 2 and 3 only at start-up (ANSEL of the PIC16F88x), or not at all: RP1 stays 0 in the scan
        high_banks = any(a >= 0x100 for a in ram) or any(st.addr >= 0x100 for st in layout.vars.values()) or any(
            isinstance(op, (ir.EepromLoad, ir.EepromSave)) for op in code.scan)
        return image(code, machine, layout, a.Assembler(part.flash_words - reserved, part.page_words),
                     MidRange(part, high_banks))


def image(code: ir.Code, machine, layout, assembler: a.Assembler, core: Core) -> Image:
    """The program's image, written through a family's assembler and core."""
    part = Part.of(machine.device)
    cx = Context(Emitter(assembler, part, ram_in_use(layout), core), part, layout, machine)
    prepare(cx, code)
    write_runtime(cx, code)
    write_routines(cx.e, layout.scratch, cx.routines)
    _write_tables(cx)
    compress_skips(assembler.items)
    config = _config(part, machine.config_word)
    try:
        assembled = assembler.assemble(processor=part.processor, config=config)
    except a.ProgramTooLarge as error:
        raise fail(FLASH_FULL, f"the program needs {error.words} words of program memory; the "
                               f"{part.title} has {assembler.flash_words}") from None
    return assembled_image(part, layout, assembled, config, cx)


def assembled_image(part: Part, layout, assembled, config: dict[int, int], cx: Context, **more) -> Image:
    """The Image of a PIC program assembled (this family's, the PIC10's), its
    listing headed by its size and how to reassemble it."""
    header = (f"; {part.title}: {len(assembled.words)} words of program memory, {layout.ram_used} bytes of RAM\n"
              f"; reassemble: gpasm -p {part.processor} FILE\n")
    return Image(
        words=assembled.words, listing=header + assembled.listing, ram_bytes=layout.ram_used,
        ram_size=layout.ram_size, flash_size=part.flash_words, flash_unit="words", warnings=[],
        symbols=symbols(layout), labels=assembled.symbols,
        segments={2 * address: value.to_bytes(2, "little") for address, value in config.items()},
        listing_suffix=".asm", loops=dict(cx.e.bounds), **more)


def _config(part: Part, setting: int | None) -> dict[int, int]:
    """Word address -> configuration word: the program's setting (its high 16
    bits are the second word of the parts with two, as LDmicro stores them),
    else the part's."""
    words = dict(part.config_words)
    if setting is not None:
        for i, address in enumerate(sorted(words)):
            words[address] = setting >> 16 * i & 0x3FFF
    return words


def symbols(layout) -> dict:
    found = {name: Symbol(loc.addr, 1, loc.bit) for name, loc in layout.bits.items()}
    found.update((name, Symbol(st.addr, st.size)) for name, st in layout.vars.items())
    return found
