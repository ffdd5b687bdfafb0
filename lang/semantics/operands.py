"""Operand forms no code is written for, whatever the part: a negative DELAY,
a variable where a constant time is needed (TIME2COUNT, TIME2DELAY), a SET
PWM resolution or a UART RECV byte count the instruction does not have, a
bit name (a contact's or coil's) where an integer variable is needed.

One definition for the lowering, which refuses such an element, and for the
check that reports it before any code is written (LD710, lang/checks).
"""

from __future__ import annotations

from collections.abc import Callable

from lang.instructions import INSTRUCTIONS
from lang.model import Element
from lang.strings import parse_format
from lang.values import as_int, is_literal, literal_value

# SET PWM resolutions: the duty value that means "always on"
PWM_FULL = {"0-100%": 100, "0-256": 256, "0-512": 512, "0-1024": 1024}

SizeOf = Callable[[str], int]


def _delay(element: Element, size_of: SizeOf) -> str | None:
    amount = str(element.args["delay"])
    if not is_literal(amount):
        return None  # a variable delay counts loops at run time
    try:
        negative = literal_value(amount) < 0
    except ValueError:
        return None  # not a number at all: LD304
    return "a delay cannot be negative" if negative else None


def _time_to_count(element: Element, size_of: SizeOf) -> str | None:
    if not isinstance(element.args["delay"], int):
        return "the T2CNT delay must be a time, not a variable"
    return None


def _time_to_delay(element: Element, size_of: SizeOf) -> str | None:
    delay = element.args["delay"]
    if not isinstance(delay, int) or delay < 0:
        return "the T2DLY delay must be a time"
    return None


def _pwm_resolution(element: Element, size_of: SizeOf) -> str | None:
    resolution = str(element.args.get("resolution") or "0-100%")
    return None if resolution in PWM_FULL else f"unknown PWM resolution '{resolution}'"


def _uart_recv(element: Element, size_of: SizeOf) -> str | None:
    name = str(element.args["var"])
    count = as_int(element.args.get("bytes", 1) or 1)
    if is_literal(name) or count <= 1 or count <= size_of(name):
        return None
    return f"UART RECV of {count} bytes into '{name}' of {size_of(name)} bytes"


# the instructions some operand form of which has no code, and what is wrong with it
REFUSALS: dict[str, Callable[[Element, SizeOf], str | None]] = {
    "DELAY": _delay,
    "TIME2COUNT": _time_to_count,
    "TIME2DELAY": _time_to_delay,
    "SET_PWM": _pwm_resolution,
    "UART_RECV": _uart_recv,
}


def operand_refusal(element: Element, size_of: SizeOf) -> str | None:
    """Why no code can be written for the element's operands, or None;
    `size_of` gives a variable's size in bytes."""
    refusal = REFUSALS.get(element.kind)
    return refusal(element, size_of) if refusal is not None else None


def bit_refusal(name: str) -> str:
    return f"'{name}' is a bit; it cannot hold an integer"


# (instruction, operand) of the table's variable, operand and delay fields, but for a PWM
# output's name (a bit) and a random seed's name (the seed has a variable of its own)
_INTEGER_FIELDS = frozenset(
    (key, f.name) for key, spec in INSTRUCTIONS.items() for f in spec.fields
    if f.kind in ("var", "operand", "delay") and f.io != "pwm" and (key, f.name) != ("SEED_RANDOM", "name"))


def integer_operand(element: Element, field: str) -> bool:
    """Whether the lowering keeps the name in this operand as an integer
    variable (a bit name there is refused): the table's variable, operand
    and delay fields, but for a PWM output's name, a RES of one (P), a
    random seed's name and a formatted string's variable when the text
    inserts none."""
    kind = element.kind
    if (kind, field) not in _INTEGER_FIELDS:
        return False
    if kind == "RES":
        return not str(element.args.get("name", "")).startswith("P")
    if kind == "FORMATTED_STRING":
        try:
            return bool(parse_format(str(element.args.get("text") or "")).digits)
        except ValueError:
            return False  # LD320 says what is wrong with the text
    return True
