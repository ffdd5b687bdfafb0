"""LDmicro's variable-usage check (`simulate.cpp: CheckVariableNames`),
computed once per run for the rules that report its findings (LD120-LD125).

Each name collects the flags its elements give it (`lang.flags`: the timer
kind, the counter kind, PWM, RES, TABLE or ANY), in evaluation order. Adding a
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

from ..flags import ANY, PWM, RES, TABLE, TIMER_FLAGS, Mark
from ..index import ProgramIndex

__all__ = ["ANY", "PWM", "RES", "TABLE", "Conflict", "Result", "analyse"]

# flags an ANY write may not meet (RTO is left out, as in LDmicro)
ANY_BLOCKERS = frozenset({PWM, "TOF", "TON", "TCY", "RTL", "THI", "TLO"})


@dataclass(frozen=True)
class Conflict:
    """A flag that clashes with the flags the name had already."""

    kind: str  # "timer-timer", "timer-other", "written", "pwm", "table"
    mark: Mark
    earlier: tuple[Mark, ...]  # the earlier marks it clashes with, in order


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
    """The walk, once per index: each name's marks in evaluation order (a
    name's flags depend on its own marks only, so the names are independent)."""
    cached = index.cache.get("varflags")
    if isinstance(cached, Result):
        return cached
    conflicts: list[Conflict] = []
    res_only: list[Mark] = []
    for marks in index.marks.values():
        have = {marks[0].flag}
        history = [marks[0]]
        for mark in marks[1:]:
            kind = _clash(mark.flag, have)
            if kind is not None:
                # LDmicro stops here; going on, the refused flag is not added
                # (as its MarkUsedVariable does), so later uses are judged
                # against the accepted ones
                conflicts.append(Conflict(kind, mark, _culprits(kind, mark.flag, history)))
                continue
            have.add(mark.flag)
            history.append(mark)
        if have == {RES}:
            res_only.append(history[0])
    result = Result(conflicts, res_only)
    index.cache["varflags"] = result
    return result
