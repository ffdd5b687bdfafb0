"""Properties: what a program must do over every input sequence, for
`ladder verify` (lang/verify, docs/verify.md). A property is one line of a
text file's PROPERTIES section or a `property` line of a scenario file:

    never Ymotor_fwd and Ymotor_rev
    always Cpos <= 100
    always Ypress implies (Xhand_left and Xhand_right)
    Yalarm within 2 s after Xfault
    reachable Ydone

The conditions are the scenario language's (lang.sim.scenario.parse_condition)
and are read, like a scenario's expectations, after each scan. Times are in
scan-independent units; the program's cycle time turns them into scans.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING

from .model import Program, PropertyLine, Span

if TYPE_CHECKING:
    from .sim.scenario import Condition

# the words that start a property, and `within` ... `after` between a response and its trigger
KINDS = ("always", "never", "reachable")
_WITHIN = re.compile(r"(?P<response>.+?)\s+within\s+(?P<time>.+?)\s+after\s+(?P<trigger>.+?)\s*\Z")


class PropertyError(ValueError):
    """A property that cannot be read, at `span`."""

    def __init__(self, message: str, span: Span):
        super().__init__(message)
        self.span = span


@dataclass(frozen=True)
class Property:
    """`always`/`never`/`reachable` `condition`, or (`within`) `condition`
    within `time_us` after `trigger`."""

    kind: str  # always, never, reachable or within
    condition: Condition
    text: str
    span: Span
    trigger: Condition | None = None
    time_us: int = 0

    def names(self) -> list[str]:
        trigger = self.trigger.names() if self.trigger is not None else []
        return list(dict.fromkeys(self.condition.names() + trigger))

    def scans(self, cycle_us: int) -> int:
        """The `within` time in whole scans, as a timer counts its delay."""
        return self.time_us // cycle_us


def parse_property(text: str, line: int, column: int = 0) -> Property:
    """The property `text`, which starts at `column` of `line` (for the
    spans of the property and of its errors)."""
    # the scenario language comes with the simulator: imported only for a program with properties
    from .sim.scenario import parse_time

    body = text.strip()
    start = column + len(text) - len(text.lstrip())
    span = Span.at(line, start, start + len(body))
    word, _, rest = body.partition(" ")
    if word in KINDS:
        condition = rest.strip()
        if not condition:
            raise PropertyError(f"`{word}` needs a condition", span)
        return Property(word, _condition(condition, line, start + body.index(condition, len(word))), body, span)
    within = _WITHIN.match(body)
    if within is None:
        raise PropertyError("cannot read the property: write `always COND`, `never COND`, `reachable COND` "
                            "or `COND within TIME after COND`", span)
    try:
        time_us = parse_time(within.group("time"))
    except ValueError as bad:
        raise PropertyError(str(bad), _group_span(within, "time", line, start)) from None
    return Property("within", _condition(within.group("response"), line, start + within.start("response")),
                    body, span, _condition(within.group("trigger"), line, start + within.start("trigger")), time_us)


def name_span(prop: Property, name: str) -> Span:
    """Where `name` is first written, as a whole word, in the property."""
    text, start = prop.text, 0
    while True:
        at = text.find(name, start)
        if at < 0:
            return prop.span
        before, after = text[at - 1:at] or " ", text[at + len(name):at + len(name) + 1] or " "
        if not (before.isalnum() or before in "_$#") and not (after.isalnum() or after in "_$#["):
            column = prop.span.col + at
            return Span.at(prop.span.line, column, column + len(name))
        start = at + 1


def _group_span(match: re.Match, group: str, line: int, start: int) -> Span:
    return Span.at(line, start + match.start(group), start + match.end(group))


def _condition(text: str, line: int, column: int) -> Condition:
    from .sim.scenario import ConditionError, parse_condition

    try:
        return parse_condition(text)
    except ConditionError as bad:
        raise PropertyError(f"cannot read the condition {text!r}: {bad}",
                            Span.at(line, column + bad.start, column + bad.end)) from None


def property_lines(program: Program) -> list[PropertyLine]:
    """The PROPERTIES section's property lines: not blank, not a `#` comment."""
    return [line for line in program.properties if line.text.strip() and not line.text.lstrip().startswith("#")]


def read_properties(program: Program) -> tuple[list[Property], list[PropertyError]]:
    """The program's properties, and the errors of the lines that cannot be read."""
    found: list[Property] = []
    problems: list[PropertyError] = []
    for line in property_lines(program):
        try:
            found.append(parse_property(line.text, line.line))
        except PropertyError as bad:
            problems.append(bad)
    return found, problems
