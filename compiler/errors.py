"""Compiler diagnostics (codes LD7xx) and the exception that carries them.

A program the back end cannot turn into a correct image fails with located
errors: an instruction or operand form it does not implement, a pin or
peripheral the part lacks, a cycle time, baud rate or PWM frequency the
crystal cannot make, a program or its variables too large for the part.
"""

from __future__ import annotations

from lang.codes import register
from lang.diagnostics import Diagnostic, error, warning

NO_TARGET = register(
    "LD701", "no part to compile for",
    "The program names no microcontroller, or one no back end compiles for. The message lists the "
    "parts `ladder build` compiles, by family (`ladder parts` marks them too); select one with "
    "`ladder build --target PART` or the MICRO setting.")
NOT_COMPILED = register(
    "LD702", "instruction or operand not compiled for the part",
    "The part's back end has no code for this instruction, or for this form of it: an instruction "
    "whose table entry lacks the family's layer, indirect register access (`#name` holding an "
    "address), a register name the part does not have.")
FLASH_FULL = register(
    "LD703", "program larger than flash",
    "The compiled program does not fit the part's flash memory. Simplify the program or choose a "
    "part with more flash.")
RAM_FULL = register(
    "LD704", "variables larger than RAM",
    "The program's variables, relays and element memories, with the stack the runtime needs, do "
    "not fit the part's RAM. LDmicro: \"RAM: Out of memory\".")
EEPROM_FULL = register(
    "LD705", "PERSIST variables larger than EEPROM",
    "The variables made persistent with PERSIST do not fit the part's EEPROM.")
BAD_CYCLE = register(
    "LD706", "cycle time not achievable",
    "The scan cycle runs on the 16-bit Timer1 clocked from the crystal through a prescaler of 1, "
    "8, 64, 256 or 1024; no setting makes this cycle time within 0.1 %. Choose another cycle "
    "time or crystal frequency.")
BAD_BAUD = register(
    "LD707", "baud rate not achievable",
    "The UART's baud rate generator cannot make the BAUD setting from the crystal within 2 % (the "
    "error LDmicro tolerates), or the divisor overflows. Choose a baud rate or crystal that "
    "divide well (e.g. 3.6864, 7.3728, 11.0592, 14.7456 MHz).")
BAUD_APPROXIMATED = register(
    "LD713", "baud rate approximated",
    "The UART's baud rate generator makes the BAUD setting from the crystal only approximately: more "
    "than 2 % off (LDmicro warns from there), but within what a receiver sampling mid-bit follows. "
    "Check the other end tolerates it, or choose a crystal that divides well (e.g. 3.6864, 7.3728, "
    "11.0592, 14.7456 MHz).")
ANALOG_PIN = register(
    "LD714", "digital pin that READ ADC makes analog",
    "On parts whose ADCON1 PCFG bits choose the analog pins (PIC16F87x, 16F819, 16F72), the A/D "
    "channels can only be made analog in fixed groups: reading AN1 makes AN0 and AN3 analog too. A "
    "digital input on such a pin always reads 0; an output is driven, but an instruction that changes "
    "another bit of the port reads the pin as 0 and may clear it. LDmicro makes every channel analog "
    "and says nothing. Move the pin, or the A/D input to a channel whose group leaves it digital.")
BAD_PWM = register(
    "LD708", "PWM output not achievable",
    "SET PWM needs an 8-bit timer output (OC0, OC0A/B, OC2, OC2A/B): Timer1 makes the scan cycle "
    "and the 16-bit timers' outputs are not compiled. Two outputs of one timer share its "
    "frequency, so they need the same one.")
PWM_FREQUENCY = register(
    "LD709", "PWM frequency approximated",
    "PWM runs an 8-bit timer in fast PWM mode: the crystal frequency divided by the timer's "
    "prescaler and by 256. The nearest of those frequencies is used; this warning says which when "
    "it is more than 5 % from the one asked.")
MOVED_PIN = register(
    "LD711", "pin number means another pin on the new part",
    "With `--target`, a pin given by its package number keeps the number, which on the new part's "
    "package is another port bit than on the program's own part. Pins given by port name (PD2) "
    "keep their port bit; give pins that way to move a program between parts.")
SCAN_OVERRUN = register(
    "LD712", "scan may not fit the cycle time",
    "The compiler bounds the longest scan of the code it wrote (`ladder build` prints it: `scan: at most N "
    "cycles = T µs of the C ms cycle`), through every call and with every loop at its bound: divisions and "
    "shifts bit by bit, BIN2BCD, DELAY, waits for the A/D converter, the UART transmitter and an EEPROM "
    "write. When that worst case is longer than the cycle time, a scan may overrun the cycle and every timer "
    "runs slow by as much (LDmicro never checks this). The warning sits on the rung that takes the most and "
    "names the loops that dominate; choose a longer cycle, a faster crystal or less work per scan.")
BAD_OPERAND = register(
    "LD710", "operand the compiler cannot use",
    "A value the code cannot be generated for: a timer period below one cycle, a malformed "
    "literal, a jump to a label that does not exist, an empty or unordered table.")


class CompileError(Exception):
    def __init__(self, diagnostics: list[Diagnostic]):
        super().__init__("; ".join(d.message for d in diagnostics))
        self.diagnostics = diagnostics


def fail(code: str, message: str, element=None) -> CompileError:
    """A CompileError with one diagnostic located on an element (or nowhere)."""
    return CompileError([error(code, message, getattr(element, "span", None))])


def note(code: str, message: str, element=None) -> Diagnostic:
    return warning(code, message, getattr(element, "span", None))
