"""Simulation diagnostics (codes LD6xx) and the exception that carries them.

A program the simulator cannot run (an instruction it does not simulate, a
timer period it cannot make, a missing label) fails when the Simulator is
built; a fault while running (division by zero, a LUT index out of range, a
runaway GOTO loop) fails the step that met it. Both raise SimulationError,
whose diagnostics are located on the element concerned.
"""

from __future__ import annotations

from ..codes import register
from ..diagnostics import Diagnostic, error

NOT_SIMULATED = register(
    "LD601", "instruction not simulated",
    "The simulator has no model of this instruction (SLEEP, SPI, I2C, stepper and pulse "
    "generators, raw SFR access, an empty rung...). Remove it to simulate the program.")
BAD_TIMER = register(
    "LD602", "timer period not achievable",
    "A timer's delay is zero or negative, shorter than one cycle, or its adjust makes the "
    "period zero or longer than the delay; LDmicro refuses to compile it.")
BAD_JUMP = register(
    "LD603", "jump target missing or ambiguous",
    "A GOTO names no LABEL, a GOSUB names no SUBPROG (or a number), a SUBPROG has no "
    "ENDSUB, or a LABEL/SUBPROG/ENDSUB name is declared twice.")
BAD_OPERAND = register(
    "LD604", "operand the simulator cannot use",
    "A destination is a literal, a literal is malformed, a table is empty or not "
    "increasing, or a formatted string has a bad escape.")
DIVIDE_BY_ZERO = register(
    "LD610", "division by zero",
    "A DIV or MOD ran with a divisor of 0; LDmicro halts its simulation here and the MCU's "
    "result is undefined.")
TABLE_INDEX = register(
    "LD611", "table index out of range",
    "A look-up table was read with an index outside 0..count-1.")
RUNAWAY = register(
    "LD612", "runaway jump loop",
    "GOTO/GOSUB jumps kept the scan from ending: more jumps in one scan than the simulator "
    "allows. On the MCU the watchdog would reset the program.")
STACK = register(
    "LD613", "subroutine stack overflow or underflow",
    "More than 8 nested GOSUB calls, or a RETURN/ENDSUB with no call to return to.")
BAD_VALUE = register(
    "LD614", "value out of the instruction's range",
    "BIN2BCD got a negative value or one above 9999; BCD2BIN got a digit above 9.")
LOCKED = register(
    "LD615", "LOCK reached",
    "A powered LOCK stops the MCU in an endless loop (a watchdog test); the simulation "
    "stops there.")
UART_STALL = register(
    "LD616", "UART receive would stall",
    "A UART RECV with `wait` needs more bytes than have been received: the MCU would stop "
    "the scan until they arrive.")


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
