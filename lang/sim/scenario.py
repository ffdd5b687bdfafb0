"""Test scenarios: a small line-based format (docs/testing.md) that drives a
program over simulated time and checks what it does.

    program ../programs/traffic.ld
    scenario red comes first
    at 0 set Xbutton1 = 1, Xbutton2 = 1
    at 0 expect Yred = 1
    from 0 to 790 ms expect Yred = 1
    at 1.2 s expect Yyellow in 0..1
    at 2 s uart "AT\\r"
    at 3 s expect uart contains "OK"

`at T` means the first scan at or after T: settings apply before it and
expectations are checked after it. Every expectation is reported: one that
fails does not stop the others, and when the run cannot go on (a fault, or
a firmware that cannot be given what comes next) each expectation it leaves
undecided is listed as not checked.
"""

from __future__ import annotations

import operator
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from pathlib import Path

from ..values import literal_value
from .errors import SimulationError
from .runtime import Simulator
from .trace import Trace, diagram, format_time
from .uart import ESCAPES, show_bytes

_TIME = re.compile(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*(us|ms|s)?\s*$")
_UNITS = {"us": 1, "ms": 1000, "s": 1_000_000, None: 1000}


class ScenarioError(Exception):
    def __init__(self, path: str, line: int, message: str):
        super().__init__(f"{path}:{line}: error: {message}")


class RunStopped(Exception):
    """Raised by a simulator's `step` when the run cannot go on from that
    scan: `why` completes "not checked: ..." for each expectation left
    undecided; `failure` is the stop's own report, if it needs one."""

    def __init__(self, why: str, failure: Failure | None = None):
        super().__init__(why)
        self.why = why
        self.failure = failure


def parse_time(text: str) -> int:
    """`1.2 s`, `500ms`, `250 us`, or a bare number of milliseconds -> microseconds."""
    match = _TIME.match(text)
    if not match:
        raise ValueError(f"bad time {text.strip()!r} (write e.g. 500 ms, 1.2 s)")
    try:
        value = Decimal(match.group(1)) * _UNITS[match.group(2)]
    except InvalidOperation:
        raise ValueError(f"bad time {text.strip()!r}") from None
    if value != value.to_integral_value():
        raise ValueError(f"time {text.strip()!r} is not a whole number of microseconds")
    return int(value)


def parse_string(text: str) -> bytes:
    """A double-quoted string with \\n \\r \\t \\\\ \\" \\0 \\e \\xHH escapes."""
    text = text.strip()
    if len(text) < 2 or text[0] != '"' or text[-1] != '"':
        raise ValueError(f"expected a double-quoted string, got {text!r}")
    out = bytearray()
    body, i = text[1:-1], 0
    while i < len(body):
        ch = body[i]
        if ch == "\\":
            nxt = body[i + 1:i + 2]
            if nxt == "x" and re.fullmatch(r"[0-9A-Fa-f]{2}", body[i + 2:i + 4]):
                out.append(int(body[i + 2:i + 4], 16))
                i += 4
                continue
            if nxt not in ESCAPES:
                raise ValueError(f"bad escape \\{nxt} in {text}")
            out += ESCAPES[nxt].encode()
            i += 2
        else:
            out += ch.encode("latin-1", errors="replace")
            i += 1
    return bytes(out)


# --- conditions: what `expect` checks, and what properties (lang/properties.py) say -------

_TOKEN = re.compile(r"\s*(?:(?P<paren>[()])|(?P<rel>==|!=|<=|>=|=|<|>)|(?P<range>\.\.)"
                    r"|(?P<literal>'(?:\\.|[^'\\])+'|[-+]?\d\w*)|(?P<word>[A-Za-z_$#](?:[\w$#\[\]]|\.(?!\.))*))")
KEYWORDS = frozenset({"and", "or", "not", "implies", "in"})
RELATIONS: dict[str, Callable] = {"=": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le,
                                  ">": operator.gt, ">=": operator.ge}


class ConditionError(ValueError):
    """A condition that cannot be read; `start` and `end` are the columns of
    the offending text in the condition."""

    def __init__(self, message: str, start: int, end: int):
        super().__init__(message)
        self.start, self.end = start, end


@dataclass(frozen=True)
class Logic:
    """How a condition combines truth values: Python's for a simulation, an
    SMT solver's for the prover (lang/verify)."""

    all: Callable = all
    any: Callable = any
    negate: Callable = operator.not_
    implies: Callable = lambda a, b: (not a) or b


PYTHON = Logic()


@dataclass(frozen=True)
class Signal:
    """A bare name: true while the signal is not 0."""

    name: str

    def evaluate(self, read: Callable, logic: Logic = PYTHON):
        return read(self.name) != 0

    def names(self) -> list[str]:
        return [self.name]

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class Compare:
    name: str
    op: str  # one of RELATIONS
    value: int | str  # a literal, or another signal read in the same scan

    def evaluate(self, read: Callable, logic: Logic = PYTHON):
        return RELATIONS[self.op](read(self.name), read(self.value) if isinstance(self.value, str) else self.value)

    def names(self) -> list[str]:
        return [self.name] + ([self.value] if isinstance(self.value, str) else [])

    def __str__(self) -> str:
        return f"{self.name} {self.op} {self.value}"


@dataclass(frozen=True)
class InRange:
    name: str
    low: int
    high: int

    def evaluate(self, read: Callable, logic: Logic = PYTHON):
        value = read(self.name)
        return logic.all([value >= self.low, value <= self.high])

    def names(self) -> list[str]:
        return [self.name]

    def __str__(self) -> str:
        return f"{self.name} in {self.low}..{self.high}"


@dataclass(frozen=True)
class Not:
    arg: Condition

    def evaluate(self, read: Callable, logic: Logic = PYTHON):
        return logic.negate(self.arg.evaluate(read, logic))

    def names(self) -> list[str]:
        return self.arg.names()

    def __str__(self) -> str:
        return f"not {_operand(self.arg, Not)}"


@dataclass(frozen=True)
class Both:
    """`and` of its parts (`any` False) or `or` (`any` True)."""

    parts: tuple[Condition, ...]
    any: bool

    def evaluate(self, read: Callable, logic: Logic = PYTHON):
        values = [part.evaluate(read, logic) for part in self.parts]
        return logic.any(values) if self.any else logic.all(values)

    def names(self) -> list[str]:
        return list(dict.fromkeys(n for part in self.parts for n in part.names()))

    def __str__(self) -> str:
        return f" {'or' if self.any else 'and'} ".join(_operand(part, self) for part in self.parts)


@dataclass(frozen=True)
class Implies:
    premise: Condition
    conclusion: Condition

    def evaluate(self, read: Callable, logic: Logic = PYTHON):
        return logic.implies(self.premise.evaluate(read, logic), self.conclusion.evaluate(read, logic))

    def names(self) -> list[str]:
        return list(dict.fromkeys(self.premise.names() + self.conclusion.names()))

    def __str__(self) -> str:
        return f"{_operand(self.premise, self)} implies {_operand(self.conclusion, self)}"


Condition = Signal | Compare | InRange | Not | Both | Implies


def _operand(part: Condition, outer) -> str:
    """A part as written inside `outer`, in parentheses where it binds less tightly."""
    simple = isinstance(part, Signal | Compare | InRange | Not)
    same = isinstance(part, Both) and isinstance(outer, Both) and part.any == outer.any
    return str(part) if simple or same else f"({part})"


def parse_condition(text: str) -> Condition:
    """`Yred = 1`, `Cpos in 0..100`, `Xa and not (Xb or Cn > 3)`, `Ya implies Xb`
    (`implies` binds least, then `or`, then `and`, then `not`); a bare name
    is true while not 0. ConditionError, with columns, for anything else."""
    parser = _Parser(text)
    condition = parser.implication()
    if parser.peek() is not None:
        raise parser.error("expected `and`, `or`, `implies` or the end of the condition")
    return condition


class _Parser:
    def __init__(self, text: str):
        self.text = text
        self.tokens: list[tuple[str, str, int, int]] = []  # (kind, text, start, end)
        position = 0
        while text[position:].strip():
            match = _TOKEN.match(text, position)
            if not match or match.end() == position:
                start = len(text) - len(text[position:].lstrip())
                raise ConditionError(f"unexpected {text[start:].split()[0]!r}", start, start + 1)
            group = match.lastgroup or ""
            word = match.group(group)
            kind = word if group == "word" and word in KEYWORDS else group
            self.tokens.append((kind, word, match.start(group), match.end(group)))
            position = match.end()
        self.next = 0

    def peek(self) -> tuple[str, str, int, int] | None:
        return self.tokens[self.next] if self.next < len(self.tokens) else None

    def take(self, kind: str) -> tuple[str, str, int, int] | None:
        token = self.peek()
        if token is not None and token[0] == kind:
            self.next += 1
            return token
        return None

    def error(self, message: str) -> ConditionError:
        token = self.peek()
        if token is None:
            end = len(self.text.rstrip())
            return ConditionError(f"{message}, at the end of {self.text.strip()!r}", end, end + 1)
        return ConditionError(f"{message}, not {token[1]!r}", token[2], token[3])

    def implication(self) -> Condition:
        premise = self.either()
        if self.take("implies"):
            return Implies(premise, self.implication())
        return premise

    def either(self) -> Condition:
        parts = [self.both()]
        while self.take("or"):
            parts.append(self.both())
        return parts[0] if len(parts) == 1 else Both(tuple(parts), any=True)

    def both(self) -> Condition:
        parts = [self.negation()]
        while self.take("and"):
            parts.append(self.negation())
        return parts[0] if len(parts) == 1 else Both(tuple(parts), any=False)

    def negation(self) -> Condition:
        if self.take("not"):
            return Not(self.negation())
        return self.primary()

    def primary(self) -> Condition:
        token = self.peek()
        if token is not None and token[1] == "(":
            self.next += 1
            inner = self.implication()
            closing = self.peek()
            if closing is None or closing[1] != ")":
                raise self.error("expected `)`")
            self.next += 1
            return inner
        name = self.take("word")
        if name is None:
            raise self.error("expected a name")
        if self.take("in"):
            low = self._literal()
            if not self.take("range"):
                raise self.error("expected `..` between the bounds")
            return InRange(name[1], low, self._literal())
        relation = self.take("rel")
        if relation is None:
            return Signal(name[1])
        op = "=" if relation[1] == "==" else relation[1]
        word = self.take("word")
        if word is not None:
            return Compare(name[1], op, word[1])
        following = self.peek()
        if following is None or following[0] != "literal":
            raise self.error("expected a number or a name")
        return Compare(name[1], op, self._literal())

    def _literal(self) -> int:
        token = self.take("literal")
        if token is None:
            raise self.error("expected a number")
        try:
            return literal_value(token[1])
        except ValueError as bad:
            raise ConditionError(str(bad), token[2], token[3]) from None


@dataclass
class Action:
    line: int
    time_us: int
    kind: str  # "set" (bit, variable or ADC reading) or "uart" (bytes received)
    name: str = ""
    value: int | bytes = 0  # bytes for "uart"


# bytes for the UART, (low, high) for `in`, another signal's name, a number, or a
# condition of several signals (or of a bare name)
Expected = bytes | tuple[int, int] | str | int | Condition


@dataclass
class Check:
    line: int
    text: str
    mode: str  # "at", "always" (from..to) or "sometime" (sometime from..to)
    start_us: int
    end_us: int
    name: str  # a signal (the first a condition reads), or "uart"
    op: str  # = != < <= > >= in, "equals"/"contains" for the UART, "holds" for a condition
    expected: Expected
    failed: bool = False
    seen: bool = False

    def describe(self) -> str:
        expected = self.expected
        if isinstance(expected, bytes):
            return f"UART output {'containing ' if self.op == 'contains' else ''}{show_bytes(expected)}"
        if isinstance(expected, tuple):
            return f"{self.name} in {expected[0]}..{expected[1]}"
        if self.op == "holds":
            return str(expected)
        return f"{self.name} {self.op} {expected}"

    def signals(self) -> list[str]:
        """The signals the expectation reads."""
        if self.name == "uart":
            return []
        if isinstance(self.expected, Signal | Compare | InRange | Not | Both | Implies):
            return self.expected.names()
        return [self.name] + ([self.expected] if isinstance(self.expected, str) else [])

    def holds(self, actual, sim: Simulator) -> bool:
        if isinstance(self.expected, bytes):
            return self.expected in actual if self.op == "contains" else actual == self.expected
        if isinstance(self.expected, tuple):
            return self.expected[0] <= actual <= self.expected[1]
        if not isinstance(self.expected, str | int):
            return bool(self.expected.evaluate(sim.value))
        # the expected value may be another signal, read in the same scan
        expected = sim.value(self.expected) if isinstance(self.expected, str) else self.expected
        return {"=": actual == expected, "!=": actual != expected, "<": actual < expected,
                "<=": actual <= expected, ">": actual > expected, ">=": actual >= expected}[self.op]


@dataclass
class Scenario:
    name: str
    path: str
    line: int
    program: Path | None
    actions: list[Action] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    run_until_us: int = 0
    # `property TEXT` lines (line number, column of the text, text): `ladder verify` proves them
    properties: list[tuple[int, int, str]] = field(default_factory=list)


@dataclass
class Failure:
    line: int
    time_ms: str
    what: str
    expected: str
    actual: str
    chart: str = ""
    checked: bool = True  # False for an expectation a stopped run left undecided

    def format(self, path: str) -> str:
        outcome = f"expected {self.expected}, got {self.actual}" if self.expected else self.actual
        text = f"{path}:{self.line}: at {self.time_ms} ms: {self.what}: {outcome}"
        return text + ("\n" + self.chart if self.chart else "")


def parse_scenarios(text: str, path: str) -> list[Scenario]:
    base = Path(path).parent
    program: Path | None = None
    scenarios: list[Scenario] = []
    for number, raw in enumerate(text.splitlines(), 1):
        line = _strip_comment_outside_quotes(raw).strip()
        if not line:
            continue
        try:
            word, _, rest = line.partition(" ")
            if word == "program":
                program = base / rest.strip()
                for scenario in scenarios:
                    scenario.program = scenario.program or program
            elif word == "scenario":
                scenarios.append(Scenario(rest.strip() or f"scenario {len(scenarios) + 1}", path, number, program))
            elif word == "property":
                if not scenarios:
                    scenarios.append(Scenario(Path(path).stem, path, number, program))
                scenarios[-1].properties.append((number, raw.index(rest.strip()), rest.strip()))
            else:
                if not scenarios:
                    scenarios.append(Scenario(Path(path).stem, path, number, program))
                _statement(scenarios[-1], number, line)
        except ValueError as bad:
            raise ScenarioError(path, number, str(bad)) from None
    for scenario in scenarios:
        if scenario.program is None:
            raise ScenarioError(path, scenario.line, "no `program` line names the program to test")
    return scenarios


def _strip_comment_outside_quotes(raw: str) -> str:
    quoted = False
    for i, ch in enumerate(raw):
        if ch == '"' and (i == 0 or raw[i - 1] != "\\"):
            quoted = not quoted
        elif ch == "#" and not quoted and not raw[i + 1:i + 2].isdigit():  # `#0x25` names a register
            return raw[:i]
    return raw


def _statement(scenario: Scenario, number: int, line: str) -> None:
    match = re.match(r"(at|from|sometime\s+from)\s+(.+?)\s+(set|uart|expect|to)\s+(.*)$", line)
    run = re.match(r"run\s+(?:for\s+|until\s+)?(.+)$", line)
    if run:
        scenario.run_until_us = max(scenario.run_until_us, parse_time(run.group(1)))
        return
    if not match:
        raise ValueError(f"cannot read {line!r}: expected `at TIME ...`, `from TIME to TIME expect ...` or `run TIME`")
    when, start_text, verb, rest = match.groups()
    start = parse_time(start_text)
    if when == "at":
        end, mode = start, "at"
    else:
        if verb != "to":
            raise ValueError("`from` needs `to TIME expect ...`")
        to = re.match(r"(.+?)\s+expect\s+(.*)$", rest)
        if not to:
            raise ValueError("`from A to B` must be followed by `expect ...`")
        end, rest, verb = parse_time(to.group(1)), to.group(2), "expect"
        mode = "always" if when == "from" else "sometime"
        if end < start:
            raise ValueError("the end of the time range is before its start")
    scenario.run_until_us = max(scenario.run_until_us, end)
    if verb == "set":
        for part in rest.split(","):
            name, eq, value = part.partition("=")
            if not eq or not name.strip():
                raise ValueError(f"expected NAME = VALUE, got {part.strip()!r}")
            scenario.actions.append(Action(number, start, "set", name.strip(), literal_value(value.strip())))
    elif verb == "uart":
        scenario.actions.append(Action(number, start, "uart", value=parse_string(rest)))
    elif verb == "expect":
        scenario.checks.append(_check(number, line, mode, start, end, rest))
    else:
        raise ValueError(f"`{verb}` needs `from`")


def _check(number: int, line: str, mode: str, start: int, end: int, rest: str) -> Check:
    uart = re.match(r"uart\s+(contains\s+)?(\".*\")\s*$", rest)
    if uart:
        return Check(number, line, mode, start, end, "uart", "contains" if uart.group(1) else "equals",
                     parse_string(uart.group(2)))
    try:
        condition = parse_condition(rest)
    except ConditionError as bad:
        raise ValueError(f"cannot read the expectation {rest!r}: {bad}; write NAME = VALUE, NAME in LOW..HIGH, "
                         "conditions joined by and, or, not, implies, or uart \"text\"") from None
    if "uart" in condition.names():
        raise ValueError(f"cannot read the expectation {rest!r}: the UART's output is bytes, write "
                         "uart \"text\" or uart contains \"text\"")
    if isinstance(condition, InRange):
        return Check(number, line, mode, start, end, condition.name, "in", (condition.low, condition.high))
    if isinstance(condition, Compare):
        return Check(number, line, mode, start, end, condition.name, condition.op, condition.value)
    return Check(number, line, mode, start, end, condition.names()[0], "holds", condition)


def run_scenario(scenario: Scenario, sim: Simulator) -> list[Failure]:
    """Run one scenario on a fresh simulator of its program."""
    cycle = sim.cycle_us
    names = _signals(scenario, sim)
    trace = Trace.watching(sim, names)
    failures: list[Failure] = []
    for check in scenario.checks:
        missing = [n for n in check.signals() if n not in names]
        if missing:
            failures.append(Failure(check.line, format_time(check.start_us, cycle), check.name,
                                    check.describe(), f"no signal {missing[0]} in the program"))
            check.failed = True
    actions = sorted(scenario.actions, key=lambda a: a.time_us)
    last_scan = -(-scenario.run_until_us // cycle)
    pending = 0
    for scan in range(last_scan + 1):
        now = scan * cycle
        while pending < len(actions) and actions[pending].time_us <= now:
            failure = _apply(sim, actions[pending], cycle)
            if failure:
                failures.append(failure)
            pending += 1
        try:
            sim.step()
        except SimulationError as problem:
            when = format_time(now, cycle)
            stop = RunStopped(f"the simulation stopped at {when} ms",
                              Failure(scenario.line, when, "the simulation stopped", "",
                                      "; ".join(f"{d.severity} {d.code} {d.message}" for d in problem.diagnostics)))
            failures += _stopped(scenario, stop, now, cycle)
            break
        except RunStopped as stop:
            failures += _stopped(scenario, stop, now, cycle)
            break
        trace.record(sim)
        for check in scenario.checks:
            _evaluate(check, sim, now, cycle, trace, failures)
    for check in scenario.checks:
        if check.mode == "sometime" and not check.seen and not check.failed:
            failures.append(Failure(check.line, format_time(check.end_us, cycle), check.name, check.describe()
                                    + f" at some time from {format_time(check.start_us, cycle)} ms",
                                    "never", _chart(trace, check, names, check.end_us)))
    return sorted(failures, key=lambda f: f.line)


def _stopped(scenario: Scenario, stop: RunStopped, now: int, cycle: int) -> list[Failure]:
    """The stop's report and every expectation it leaves undecided (marked
    failed): one whose time or time range reaches the scan at `now`, which
    did not run or ran only in part, and that has not already failed (or,
    for a `sometime`, held)."""
    found = [stop.failure] if stop.failure else []
    for check in scenario.checks:
        settled = check.failed or check.seen and check.mode != "always" or _last_due(check, cycle) < now
        if not settled:
            check.failed = True
            found.append(Failure(check.line, format_time(max(check.start_us, now), cycle), check.name, "",
                                 f"not checked ({check.describe()}): {stop.why}", checked=False))
    return found


def _last_due(check: Check, cycle: int) -> int:
    """The time of the last scan after which `check` is evaluated."""
    if check.mode == "at":
        return -(-check.start_us // cycle) * cycle
    return check.end_us // cycle * cycle


def _signals(scenario: Scenario, sim: Simulator) -> list[str]:
    wanted = [a.name for a in scenario.actions if a.kind == "set"] + [n for c in scenario.checks for n in c.signals()]
    return sorted({n for n in wanted if sim.knows(n)})


def _apply(sim: Simulator, action: Action, cycle: int) -> Failure | None:
    try:
        if isinstance(action.value, bytes):
            sim.uart_receive(action.value)
        else:
            sim.set(action.name, action.value)
    except (KeyError, ValueError) as bad:
        return Failure(action.line, format_time(action.time_us, cycle), action.name or "uart", "a settable name",
                       str(bad).strip('"'))
    return None


def _evaluate(check: Check, sim: Simulator, now: int, cycle: int, trace: Trace, failures: list) -> None:
    if check.failed or check.seen and check.mode == "sometime":
        return
    due = check.start_us <= now <= check.end_us if check.mode != "at" else \
        now >= check.start_us and now - cycle < check.start_us
    if not due:
        return
    actual: bytes | int = sim.uart_output() if check.name == "uart" else sim.value(check.name)
    if check.holds(actual, sim):
        check.seen = True
        return
    if check.mode == "sometime":
        return
    check.failed = True
    if isinstance(actual, bytes):
        shown = show_bytes(actual)
    elif check.op == "holds":
        shown = ", ".join(f"{name} = {sim.value(name)}" for name in check.signals())
    else:
        shown = str(actual)
    what = ", ".join(check.signals()) if check.op == "holds" else check.name
    failures.append(Failure(check.line, format_time(now, cycle), what, check.describe(), shown,
                            _chart(trace, check, trace.names, now)))


def _chart(trace: Trace, check: Check, names: list[str], at_us: int) -> str:
    if check.name == "uart":
        return ""
    own = check.signals()
    shown = (own + [n for n in names if n not in own])[:max(8, len(own))]
    start = max(0, min(check.start_us, at_us - 40 * trace.cycle_us))
    start -= start % trace.cycle_us
    return diagram(trace, shown, start, trace.end_us)
