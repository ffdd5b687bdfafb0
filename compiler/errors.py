"""Compiler diagnostics (codes LD7xx) and the exception that carries them.

A program the back end cannot turn into a correct image fails with located
errors: an instruction or operand form it does not implement, a pin or
peripheral the part lacks, a program or its variables too large for the part.
What the part's data alone decides (a cycle time its timer cannot make,
LD706; a baud rate its UART cannot make, LD707, or only approximates, LD713;
a PWM output its timer cannot make, LD708, or only approximates, LD709; a
digital pin an A/D input makes analog, LD714; PERSIST data beyond the EEPROM,
LD705; a `#` name that is none of the part's registers, LD702; an operand
form with no code, LD710) is a check rule (lang/checks), which `ladder check`
runs and the build runs first. Only LD703, LD704 and LD712 need the code.
"""

from __future__ import annotations

from lang.codes import code
from lang.diagnostics import Diagnostic, error, warning
from lang.semantics import errors as lowering

NO_TARGET = code("LD701")
NOT_COMPILED = code("LD702")
FLASH_FULL = code("LD703")
RAM_FULL = code("LD704")
EEPROM_FULL = code("LD705")
MOVED_PIN = code("LD711")
SCAN_OVERRUN = code("LD712")
BAD_OPERAND = code("LD710")
INTERNAL_CLOCK = code("LD716")

# the code of each kind of problem the lowering meets, when no check names it
LOWERING_CODES = {lowering.OPERAND: BAD_OPERAND, lowering.TIMER: BAD_OPERAND, lowering.JUMP: BAD_OPERAND,
                  lowering.UNSUPPORTED: NOT_COMPILED, lowering.EEPROM: EEPROM_FULL}


class CompileError(Exception):
    def __init__(self, diagnostics: list[Diagnostic]):
        super().__init__("; ".join(d.message for d in diagnostics))
        self.diagnostics = diagnostics


def fail(code: str, message: str, element=None) -> CompileError:
    """A CompileError with one diagnostic located on an element (or nowhere)."""
    return CompileError([error(code, message, getattr(element, "span", None))])


def note(code: str, message: str, element=None) -> Diagnostic:
    return warning(code, message, getattr(element, "span", None))


def lowering_failed(problem: lowering.LoweringError) -> CompileError:
    return fail(problem.check or LOWERING_CODES[problem.kind], problem.message, problem.element)
