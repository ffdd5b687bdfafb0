"""What a name is, from its first letter: LDmicro gives every name its role
(input pin, relay, timer, Modbus register...) by that letter alone."""

from __future__ import annotations

# First letter of a name -> (short role, what it means)
ROLES: dict[str, tuple[str, str]] = {
    "X": ("digital input", "a digital input pin (1 bit); it needs a pin to be compiled"),
    "Y": ("digital output", "a digital output pin (1 bit); it needs a pin to be compiled"),
    "R": ("internal relay", "an internal relay: a bit in memory"),
    "M": ("Modbus coil", "a Modbus coil (a bit)"),
    "I": ("Modbus discrete input", "a Modbus discrete input (a bit)"),
    "P": ("PWM output", "a PWM output pin"),
    "T": ("timer", "a timer accumulator: an integer counting PLC cycles"),
    "C": ("counter", "a counter accumulator (an integer)"),
    "A": ("A/D input", "an A/D converter reading (an integer) bound to an analog pin"),
    "H": ("Modbus holding register", "a Modbus holding register (an integer)"),
    "#": ("hardware register", "a hardware register (#PORTx, #PINx, #TRISx, #<address>, #<var> indirect)"),
    "$": ("compiler-internal name", "a name the compiler reserves for itself"),
}
GENERAL = ("integer variable", "a general-purpose signed integer variable (1 to 4 bytes, 2 by default)")
BIT_PREFIXES = "XYRMIP"
PIN_PREFIXES = "XYAP"  # names that take a pin of the part
# LDmicro's output that is high while the scan runs (the cycle duty setting)
CYCLE_DUTY_PIN = "YPlcCycleDuty"


def role(name: str) -> tuple[str, str]:
    """(short role, sentence) for a name, from its first letter."""
    return ROLES.get(name[:1], GENERAL)
