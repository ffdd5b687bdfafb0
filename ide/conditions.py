"""Conditions on a running simulation, as `ladder.sim.runUntil` takes them:
`Yred = 1`, `Ccount >= 3`, `Tdly != Tmax` (a name, a comparison, a literal
or another name). The same comparisons as the `expect` lines of test
scenarios (docs/testing.md)."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from lang.values import is_literal, literal_value

if TYPE_CHECKING:
    from lang.sim import Simulator

_CONDITION = re.compile(r"\s*(?P<name>[A-Za-z_$#@][\w$#@.\[\]]*)\s*(?P<op>==|=|!=|<=|>=|<|>)\s*"
                        r"(?P<value>\S+)\s*\Z")
_OPS: dict[str, Callable[[int, int], bool]] = {
    "=": lambda a, b: a == b, "!=": lambda a, b: a != b, "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
}


@dataclass(frozen=True)
class Condition:
    name: str
    op: str
    value: int | str  # a number, or the name of another signal

    def holds(self, sim: Simulator) -> bool:
        """KeyError when a name is not in the program."""
        actual = sim.value(self.name)
        expected = sim.value(self.value) if isinstance(self.value, str) else self.value
        return _OPS[self.op](actual, expected)

    def __str__(self) -> str:
        return f"{self.name} {self.op} {self.value}"


def parse_condition(text: str) -> Condition:
    """ValueError with a reason for anything else."""
    match = _CONDITION.match(text or "")
    if not match:
        raise ValueError(f"cannot read the condition {text!r}: write NAME = VALUE, or with != < <= > >=")
    op = "=" if match.group("op") in ("=", "==") else match.group("op")
    value = match.group("value")
    if is_literal(value):
        return Condition(match.group("name"), op, literal_value(value))
    if not re.fullmatch(r"[A-Za-z_$#@][\w$#@.\[\]]*", value):
        raise ValueError(f"{value!r} is neither a number nor a name")
    return Condition(match.group("name"), op, value)
