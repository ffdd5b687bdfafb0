"""Simulation diagnostics (codes LD6xx) and the exception that carries them.

A program the simulator cannot run (an instruction it does not simulate, a
timer period it cannot make, a missing label) fails when the Simulator is
built; a fault while running (division by zero, a LUT index out of range, a
runaway GOTO loop) fails the step that met it. Both raise SimulationError,
whose diagnostics are located on the element concerned.
"""

from __future__ import annotations

from ..codes import code
from ..diagnostics import Diagnostic, error

NOT_SIMULATED = code("LD601")
BAD_TIMER = code("LD602")
BAD_JUMP = code("LD603")
BAD_OPERAND = code("LD604")
DIVIDE_BY_ZERO = code("LD610")
TABLE_INDEX = code("LD611")
RUNAWAY = code("LD612")
STACK = code("LD613")
BAD_VALUE = code("LD614")
LOCKED = code("LD615")
UART_STALL = code("LD616")


class SimulationError(Exception):
    """The program cannot be simulated, or a scan failed. `diagnostics` are
    located; `scan` is the failing scan's number (None before running)."""

    def __init__(self, diagnostics: list[Diagnostic], scan: int | None = None,
                 time_ms: float | None = None):
        super().__init__("; ".join(d.message for d in diagnostics))
        self.diagnostics = diagnostics
        self.scan = scan
        self.time_ms = time_ms


class Fault(Exception):
    """Raised by compiled scan code: element number and message; the
    simulator turns it into a located SimulationError."""

    def __init__(self, element: int, code: str, message: str):
        super().__init__(message)
        self.element = element
        self.code = code
        self.message = message
        self.done = 0  # scans the run finished before this one


def located(code: str, message: str, element) -> Diagnostic:
    return error(code, message, element.span if element is not None else None)
