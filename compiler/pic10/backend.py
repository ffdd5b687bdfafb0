"""The PIC10F200/202 back end: intermediate code to 12-bit program words,
the configuration word and a gpasm listing.

The instruction patterns and routines are the PIC16 back end's
(compiler/pic16/), written through the shared emitter with a `Core` of one
bank; the baseline's assembler (asm.py) writes the few mid-range
instructions it lacks with its own. What is the baseline's own: the
runtime (Timer0 polled for the cycle, OPTION and TRIS), the tables (a
computed jump in the first 256 words), the tables and routines placed first
(a CALL reaches only the first 256 words), the scratch bytes only the code
uses (16 or 24 bytes of RAM), and the refusals: program memory, RAM, the
two-level stack.
"""

from __future__ import annotations

import re
from dataclasses import replace

from lang.codes import code as diagnostic_code
from lang.hardware import cycle_refusal, cycle_setting
from lang.semantics import ir

from ..errors import FLASH_FULL, RAM_FULL, fail
from ..image import Image
from ..pic16.asm import Goto, Ins, Label, ProgramTooLarge
from ..pic16.backend import assembled_image, ram_in_use
from ..pic16.emit import PCL, Emitter, W, compress_skips
from ..pic16.memory import SCRATCH_BYTES, Layout, allocate
from ..pic16.part import Part
from ..pic16.peripherals import DELAY_LOOP_CYCLES
from ..pic16.routines import write_routines
from ..pic16.select import Context, prepare
from . import flow as pic10_flow
from . import isa
from .asm import Assembler, OutOfReach
from .core import BaselineCore
from .peephole import jump_targets, sign_fixes_folded, start_up_trimmed, w_kept, without_idle_labels
from .ranges import never_negative
from .runtime import CYCLE_BYTES, scan_limit, write_runtime
from .stack import deepest

CYCLE_UNACHIEVABLE = diagnostic_code("LD706")
# the scratch bytes (and the assembler's own byte, the last) are named from here until placed:
# no file register has such an address, so the encoder refuses one left unplaced
UNPLACED = 0x100
FILE_PATTERNS = ("fd", "f", "fb")


def _write_tables(cx: Context) -> None:
    """Each table: a routine that jumps to RETLW data[A0] by adding the
    index to PCL (the assembler keeps every entry in the first 256 words)."""
    e, s = cx.e, cx.layout.scratch
    for data, name in cx.tables.items():
        e.label(name, loop=True)
        e.ins("movf", s[0], W)
        e.ins("addwf", PCL, 1)
        e.end_path()
        e.asm.table(f"{name}_data", data)


def _place_scratch(items: list, layout: Layout, part: Part) -> None:
    """The scratch bytes the code names get RAM of their own, the others none."""
    named = sorted({item.args[0] for item in items if isinstance(item, Ins)
                    and isa.INSTRUCTIONS[item.op].pattern in FILE_PATTERNS and item.args[0] >= UNPLACED})
    taken = _in_ram(ram_in_use(layout), part)
    free = [address for span in part.ram_ranges() for address in span if address not in taken]
    if len(named) > len(free):
        raise fail(RAM_FULL, f"the variables, bits and cycle timer need {len(taken)} bytes of RAM and the "
                             f"compiler's patterns {len(named)} scratch bytes; the {part.title} has {layout.ram_size}")
    placed = dict(zip(named, free))
    for item in items:
        if isinstance(item, Ins) and item.args and item.args[0] in placed:
            item.args = (placed[item.args[0]], *item.args[1:])
    layout.scratch = tuple(placed.get(address, address) for address in layout.scratch)
    layout.ram_used += len(named)


def _in_ram(addresses, part: Part) -> frozenset[int]:
    ram = {address for span in part.ram_ranges() for address in span}
    return frozenset(address for address in addresses if address in ram)


def _callee(label: str) -> str:
    """A call target as a message names it: a GOSUB's subroutine by its first rung, a routine by its label."""
    rung = re.fullmatch(r"rung(\d+)", label)
    return f"the subroutine at rung {rung.group(1)}" if rung else label


def _routines_first(items: list, split: int, kept: set[str]) -> None:
    """The tables and routines (items[split:]) at the start, behind a GOTO to
    the runtime; each part's skips compressed on its own and rewritten
    (peephole.py). `kept`: the labels that stay where nothing jumps to them
    (the budget's loop heads)."""
    parts = [without_idle_labels(part, kept | jump_targets(items)) for part in (items[:split], items[split:])]
    for part in parts:
        compress_skips(part)
    targets = kept | jump_targets(parts[0] + parts[1])
    runtime, routines = (sign_fixes_folded(w_kept(without_idle_labels(part, targets))) for part in parts)
    runtime = start_up_trimmed(runtime, "scan")
    items[:] = [Goto("main"), *routines, Label("main"), *runtime] if routines else runtime


class Pic10Backend:
    family = "pic10"
    delay_loop_cycles = DELAY_LOOP_CYCLES
    rungs_by_jumps = True
    flow = pic10_flow

    def compile(self, code: ir.Code, machine) -> Image:
        part = Part.of(machine.device)
        # the internal oscillator is the only clock: the program's crystal setting does not change it
        clock_hz = part.facts["clock_hz"]
        if cycle_setting(part.device, clock_hz, machine.cycle_us, free=True) is None:
            raise fail(CYCLE_UNACHIEVABLE, cycle_refusal(part.device, clock_hz, machine.cycle_us, free=True))
        layout = allocate(code, part, machine, True, scratch_bytes=0, clock_bytes=CYCLE_BYTES)
        layout.scratch = tuple(range(UNPLACED, UNPLACED + SCRATCH_BYTES))
        # the last word keeps the oscillator calibration
        counts = frozenset(layout.vars[name].addr + layout.vars[name].size - 1 for name in never_negative(code)
                           if name in layout.vars and layout.vars[name].ram)
        assembler = Assembler(part.flash_words - 1, part.facts["call_words"], UNPLACED + SCRATCH_BYTES, counts)
        ram = _in_ram(ram_in_use(layout), part) | set(layout.scratch)
        cx = Context(Emitter(assembler, part, frozenset(ram), BaselineCore()), part, layout,
                     replace(machine, crystal_hz=clock_hz), self.delay_loop_cycles)
        config = {address: (value if machine.config_word is None else machine.config_word & 0xFFF)
                  for address, value in part.config_words}
        watchdog = part.config_field("WDTE")
        assert watchdog is not None  # both parts have the field (gputils' _WDTE_ON/_WDTE_OFF)
        prepare(cx, code)
        write_runtime(cx, code, clock_hz, watchdog=bool(next(iter(config.values())) & watchdog.mask))
        split = len(assembler.items)
        # tables first: every entry must lie in the first 256 words, of a routine only its entry
        _write_tables(cx)
        write_routines(cx.e, layout.scratch, cx.routines)
        _routines_first(assembler.items, split, set(cx.e.bounds))
        _place_scratch(assembler.items, layout, part)
        try:
            assembled = assembler.assemble(processor=part.processor, config=config)
        except ProgramTooLarge as error:
            raise fail(FLASH_FULL, f"the program needs {error.words} words of program memory; the "
                                   f"{part.title} has {part.flash_words - 1} (its last word keeps the "
                                   "oscillator calibration)") from None
        except OutOfReach as error:
            raise fail(FLASH_FULL, f"'{error.label}' reaches word {error.address}: a CALL and a table's jump reach "
                                   f"only the first {part.facts['call_words']} words of the {part.title}") from None
        chain = deepest(assembled.words)
        if len(chain) > part.facts["stack"]:
            names: dict[int, str] = {}
            for label, address in assembled.symbols.items():
                if not label.startswith("_"):  # the patterns' own labels name nothing a user wrote
                    names.setdefault(address, _callee(label))
            calls = ", which calls ".join(names.get(address, f"word {address}") for address in chain)
            gosubs = machine.elements("GOSUB")
            raise fail(RAM_FULL, f"the program calls {calls}: {len(chain)} return addresses at once; the "
                                 f"{part.title}'s hardware stack holds {part.facts['stack']}",
                       gosubs[0] if gosubs else None)
        return assembled_image(part, layout, assembled, config, cx,
                               scan_limit=scan_limit(part, clock_hz, machine.cycle_us))
