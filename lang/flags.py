"""The flags LDmicro's variable check gives names (its `CheckVariableNames`):
which names each element marks, and with what.

Each element marks some of its operands with a flag: the timer kind (TON,
TOF, ...), the counter kind, PWM, RES, TABLE (a LUT/PWL table name) or ANY
(written by a general instruction, or a label). The symbol table
(`lang.index`) records every mark of every name; the checks
(`lang.checks.varflags`) judge the marks of each name in order.
"""

from __future__ import annotations

from typing import NamedTuple

from .instructions import COUNTERS, INSTRUCTIONS, TIMERS
from .labels import token
from .model import Element
from .values import as_int, is_literal, is_literal_fast

RES = "RES"
PWM = "PWM"
TABLE = "TABLE"
ANY = "ANY"
TIMER_FLAGS = frozenset(TIMERS)


class Mark(NamedTuple):
    """One flag given to a name by one element."""

    name: str
    flag: str
    rung: int
    element: Element
    field: str


# element kind -> the operands that get ANY: the table's, and every label (a jump target)
_ANY_FIELDS: dict[str, tuple[str, ...]] = {
    key: spec.ldmicro_written or tuple(f.name for f in spec.fields if f.kind == "label")
    for key, spec in INSTRUCTIONS.items()
    if spec.ldmicro_written or any(f.kind == "label" for f in spec.fields)
}
# STEPPER, PULSER and NPULSE: the operand LDmicro reads as the table name
_PULSE_KINDS = {"STEPPER": "name", "PULSER": "p1", "NPULSE": "counter"}
# the segment decoders also read a source that is not a literal
_SOURCE_TOO = ("7SEGMENTS", "9SEGMENTS", "14SEGMENTS", "16SEGMENTS")

# element kind -> ((operand, flag), ...) for the kinds a simple table describes
_SIMPLE: dict[str, tuple[tuple[str, str], ...]] = {}
for _kind in TIMER_FLAGS:
    _SIMPLE[_kind] = (("name", _kind),)
for _kind in COUNTERS:
    _SIMPLE[_kind] = (("name", _kind),)
_SIMPLE["SET_PWM"] = (("name", PWM),)
_SIMPLE["RES"] = (("name", RES),)
for _kind, _fields in _ANY_FIELDS.items():
    _SIMPLE[_kind] = tuple((f, ANY) for f in _fields)
for _kind in ("LOOK_UP_TABLE", "PIECEWISE_LINEAR"):
    _SIMPLE[_kind] = (("table", TABLE),) + _SIMPLE[_kind]
for _kind in _SOURCE_TOO:
    _SIMPLE[_kind] = _SIMPLE[_kind] + (("src", ANY),)

MARKING = frozenset(_SIMPLE) | {"SHIFT_REGISTER"} | frozenset(_PULSE_KINDS)
_new = tuple.__new__  # a NamedTuple without its Python-level __new__ (hot loop)


def shift_stages(element: Element) -> int:
    """A shift register's number of stages (0 when it is not a number)."""
    try:
        return as_int(element.args.get("stages") or 0)
    except ValueError:
        return 0


def marks(rung: int, element: Element) -> list[Mark]:
    """The flags one element gives to names, in LDmicro's order."""
    kind = element.kind
    args = element.args
    found = []
    simple = _SIMPLE.get(kind)
    if simple is not None:
        for field, flag in simple:
            text = args.get(field)
            if text.__class__ is str and text and text != "(none)" and not is_literal_fast(text):
                found.append(_new(Mark, (text, flag, rung, element, field)))
    elif kind == "SHIFT_REGISTER":
        base = token(args.get("name"))
        stages = shift_stages(element)
        if base:
            for i in range(1, stages):
                found.append(Mark(f"{base}{i}", ANY, rung, element, "name"))
    elif kind in _PULSE_KINDS:
        # the first operand names a table; C<name>Dec/Inc/P are its counters
        first = _PULSE_KINDS[kind]
        base = token(args.get(first))
        if base and not is_literal(base):
            found.append(Mark(base, TABLE, rung, element, first))
            for suffix in ("Dec", "Inc", "P"):
                found.append(Mark(f"C{base}{suffix}", ANY, rung, element, first))
    return found
