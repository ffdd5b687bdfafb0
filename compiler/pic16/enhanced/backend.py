"""The enhanced mid-range back end: the PIC16 back end's patterns, runtime
and routines (compiler/pic16/), written through the shared emitter with the
enhanced core (`EnhancedCore`: BSR banks set by MOVLB, FSR0 over the
traditional data memory, the busiest output latch through INDF1) and laid
out by the enhanced assembler (MOVLP pages, the enhanced instruction table).
The arithmetic patterns use the core's ADDWFC, SUBWFB, LSLF, LSRF and ASRF
(compiler/pic16/integers.py asks `Core.carry_ops`)."""

from __future__ import annotations

from lang.semantics import ir

from ...image import Image
from ..backend import image
from ..memory import allocate
from ..part import Part
from ..runtime import free_running
from .asm import Assembler
from .core import EnhancedCore
from .latch import busiest_latch


def compile_enhanced(code: ir.Code, machine) -> Image:
    part = Part.of(machine.device)
    layout = allocate(code, part, machine, free_running(code, part, machine))
    alias = busiest_latch(code, layout, part, machine)
    return image(code, machine, layout, Assembler(part.flash_words, part.page_words, alias), EnhancedCore(part, alias))
