"""LDmicro's variable-usage check (`simulate.cpp: CheckVariableNames`,
ldmicro-formats.md §4.3(c)), computed once per run for the rules that
report its findings (LD120-LD125).

The rungs are walked in evaluation order and each name collects flags: the
timer kind (TON, TOF, ...), the counter kind, PWM, RES, TABLE (a LUT/PWL
table name) or ANY (written by a general instruction, or a label). Adding a
flag F to a name that already has flags E conflicts when

* F is a timer kind and E holds anything but RES;
* F is PWM and E holds anything but RES and PWM;
* F is TABLE and E holds anything but TABLE;
* F is ANY and E holds PWM, TOF, TON, TCY, RTL, THI or TLO (not RTO, not counters).

Counters and RES never conflict. The check is order dependent, as LDmicro's
is: `MOV Tx` after `RTO Tx` passes, before it fails. After the walk, a name
that only RES ever used is an error of its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

from ..index import ProgramIndex
from ..index import is_literal_fast as _is_literal
from ..instructions import COUNTERS, INSTRUCTIONS, TIMERS
from ..labels import token
from ..model import Element
from ..values import is_literal

RES = "RES"
PWM = "PWM"
TABLE = "TABLE"
ANY = "ANY"
TIMER_FLAGS = frozenset(TIMERS)
# flags an ANY write may not meet (RTO is left out, as in LDmicro)
ANY_BLOCKERS = frozenset({PWM, "TOF", "TON", "TCY", "RTL", "THI", "TLO"})

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


class Mark(NamedTuple):
    """One flag given to a name by one element."""

    name: str
    flag: str
    rung: int
    element: Element
    field: str


@dataclass(frozen=True)
class Conflict:
    """A flag that clashes with the flags the name had already."""

    kind: str  # "timer-timer", "timer-other", "written", "pwm", "table"
    mark: Mark
    earlier: tuple[Mark, ...]  # the earlier marks it clashes with, in order


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


def _marks(rung: int, element: Element) -> list[Mark]:
    """The flags one element gives to names, in LDmicro's order."""
    kind = element.kind
    args = element.args
    found = []
    simple = _SIMPLE.get(kind)
    if simple is not None:
        for field, flag in simple:
            text = args.get(field)
            if text.__class__ is str and text and text != "(none)" and not _is_literal(text):
                found.append(_new(Mark, (text, flag, rung, element, field)))
    elif kind == "SHIFT_REGISTER":
        base = token(args.get("name"))
        try:
            stages = int(args.get("stages") or 0)
        except (TypeError, ValueError):
            stages = 0
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


_new = tuple.__new__  # a NamedTuple without its Python-level __new__ (hot loop)
_MARKING = frozenset(_SIMPLE) | {"SHIFT_REGISTER"} | frozenset(_PULSE_KINDS)


def _clash(flag: str, flags: set[str]) -> str | None:
    """The kind of conflict adding `flag` to `flags` makes, or None."""
    if flag in TIMER_FLAGS:
        if flags & TIMER_FLAGS:
            return "timer-timer"
        if flags - {RES}:
            return "timer-other"
        return None
    if flag == PWM:
        return "pwm" if flags - {RES, PWM} else None
    if flag == TABLE:
        return "table" if flags - {TABLE} else None
    if flag == ANY:
        return "written" if flags & ANY_BLOCKERS else None
    return None


def _culprits(kind: str, flag: str, marks: list[Mark]) -> tuple[Mark, ...]:
    """The earlier marks that make the conflict, for the message and Related."""
    if kind == "timer-timer":
        keep = [m for m in marks if m.flag in TIMER_FLAGS]
    elif kind == "timer-other":
        keep = [m for m in marks if m.flag != RES]
    elif kind == "pwm":
        keep = [m for m in marks if m.flag not in (RES, PWM)]
    elif kind == "table":
        keep = [m for m in marks if m.flag != TABLE]
    else:
        keep = [m for m in marks if m.flag in ANY_BLOCKERS]
    return tuple(keep)


@dataclass
class Result:
    conflicts: list[Conflict]
    res_only: list[Mark]  # the first RES of every name only RES ever used


def analyse(index: ProgramIndex) -> Result:
    """The walk, once per index."""
    cached = index.cache.get("varflags")
    if cached is not None:
        return cached
    flags: dict[str, set[str]] = {}
    history: dict[str, list[Mark]] = {}
    conflicts: list[Conflict] = []
    for rung, element in index.elements:
        if element.kind not in _MARKING:
            continue
        for mark in _marks(rung, element):
            have = flags.get(mark.name)
            if have is None:
                flags[mark.name] = {mark.flag}
                history[mark.name] = [mark]
                continue
            kind = _clash(mark.flag, have)
            if kind is not None:
                # LDmicro stops here; going on, the refused flag is not added
                # (as its MarkUsedVariable does), so later uses are judged
                # against the accepted ones
                conflicts.append(Conflict(kind, mark, _culprits(kind, mark.flag, history[mark.name])))
                continue
            have.add(mark.flag)
            history[mark.name].append(mark)
    res_only = [history[name][0] for name, have in flags.items() if have == {RES}]
    result = Result(conflicts, res_only)
    index.cache["varflags"] = result
    return result
