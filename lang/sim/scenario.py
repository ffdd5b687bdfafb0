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

import re
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from pathlib import Path

from ..values import is_literal, literal_value
from .errors import SimulationError
from .runtime import Simulator
from .trace import Trace, diagram, format_time
from .uart import ESCAPES, show_bytes

_TIME = re.compile(r"\s*(\d+(?:\.\d*)?|\.\d+)\s*(us|ms|s)?\s*$")
_UNITS = {"us": 1, "ms": 1000, "s": 1_000_000, None: 1000}
_CONDITION = re.compile(r"(?P<name>[A-Za-z_$#][\w$#.\[\]]*)\s*(?:(?P<op>==|=|!=|<=|>=|<|>)\s*(?P<value>\S+)"
                        r"|\s+in\s+(?P<low>\S+?)\s*\.\.\s*(?P<high>\S+))\s*$")


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


@dataclass
class Action:
    line: int
    time_us: int
    kind: str  # "set" (bit, variable or ADC reading) or "uart" (bytes received)
    name: str = ""
    value: int | bytes = 0  # bytes for "uart"


# bytes for the UART, (low, high) for `in`, another signal's name, or a number
Expected = bytes | tuple[int, int] | str | int


@dataclass
class Check:
    line: int
    text: str
    mode: str  # "at", "always" (from..to) or "sometime" (sometime from..to)
    start_us: int
    end_us: int
    name: str  # a signal, or "uart"
    op: str  # = != < <= > >= in, "equals"/"contains" for the UART
    expected: Expected
    failed: bool = False
    seen: bool = False

    def describe(self) -> str:
        expected = self.expected
        if isinstance(expected, bytes):
            return f"UART output {'containing ' if self.op == 'contains' else ''}{show_bytes(expected)}"
        if isinstance(expected, tuple):
            return f"{self.name} in {expected[0]}..{expected[1]}"
        return f"{self.name} {self.op} {expected}"

    def holds(self, actual, sim: Simulator) -> bool:
        if isinstance(self.expected, bytes):
            return self.expected in actual if self.op == "contains" else actual == self.expected
        if isinstance(self.expected, tuple):
            return self.expected[0] <= actual <= self.expected[1]
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
        elif ch == "#" and not quoted:
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
    condition = _CONDITION.match(rest)
    if not condition:
        raise ValueError(f"cannot read the expectation {rest!r}: write NAME = VALUE, NAME in LOW..HIGH "
                         "or uart \"text\"")
    if condition.group("name") == "uart":
        raise ValueError(f"cannot read the expectation {rest!r}: the UART's output is bytes, write "
                         "uart \"text\" or uart contains \"text\"")
    expected: Expected
    if condition.group("low") is not None:
        expected = (literal_value(condition.group("low")), literal_value(condition.group("high")))
        op = "in"
    else:
        op = "=" if condition.group("op") in ("=", "==") else condition.group("op")
        value = condition.group("value")
        expected = literal_value(value) if is_literal(value) else value
    return Check(number, line, mode, start, end, condition.group("name"), op, expected)


def run_scenario(scenario: Scenario, sim: Simulator) -> list[Failure]:
    """Run one scenario on a fresh simulator of its program."""
    cycle = sim.cycle_us
    names = _signals(scenario, sim)
    trace = Trace.watching(sim, names)
    failures: list[Failure] = []
    for check in scenario.checks:
        missing = [n for n in (check.name, check.expected) if isinstance(n, str) and n != "uart" and n not in names]
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
    known = sim.variables()
    wanted = [a.name for a in scenario.actions if a.kind == "set"] + [c.name for c in scenario.checks] \
        + [c.expected for c in scenario.checks if isinstance(c.expected, str)]
    return sorted({n for n in wanted if n in known})


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
    failures.append(Failure(check.line, format_time(now, cycle), check.name, check.describe(),
                            show_bytes(actual) if isinstance(actual, bytes) else str(actual),
                            _chart(trace, check, trace.names, now)))


def _chart(trace: Trace, check: Check, names: list[str], at_us: int) -> str:
    if check.name == "uart":
        return ""
    shown = [check.name] + [n for n in names if n != check.name][:7]
    start = max(0, min(check.start_us, at_us - 40 * trace.cycle_us))
    start -= start % trace.cycle_us
    return diagram(trace, shown, start, trace.end_us)
