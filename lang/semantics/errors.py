"""What the lowering cannot turn into code: a malformed operand, a timer
period the cycle time cannot make, a jump with no target, an instruction
the consumer does not run, more PERSIST variables than the EEPROM holds.

The lowering serves the simulator and the compiler, which report the same
problem under their own codes (LD6xx and LD7xx): a `LoweringError` names the
kind of problem, and each consumer's table gives the code; `check` is the
code of the check that reports the same problem, which the compiler uses.
"""

from __future__ import annotations

OPERAND, TIMER, JUMP, UNSUPPORTED, EEPROM = "operand", "timer", "jump", "unsupported", "eeprom"


class LoweringError(Exception):
    def __init__(self, kind: str, message: str, element=None, check: str | None = None):
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.element = element
        self.check = check


def fail(kind: str, message: str, element=None, check: str | None = None) -> LoweringError:
    return LoweringError(kind, message, element, check)
