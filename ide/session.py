"""A simulation of a document in the editor: the simulator
(lang.sim.Simulator) running the program of one version of the document, the
fault that stopped it (a run-time fault is part of the state, not a failed
command), the elements the last scan energized (where their glyphs are
drawn), what the UART sent, and the values shown beside the drawing. When
the document changes, the edited program is loaded into the running
simulator: names that still exist keep their values.

`set` and `toggle` change a value without running a scan; the next step (or
the real-time timer) shows its effect, as in a PLC whose inputs change
between scans. Scheduling (real time, a run until a condition that lets
other requests in) is the server's.

A simulation may replay a scenario's inputs (`Replay`: its `at T set` and
`at T uart` lines, as `ladder test` runs them): each is applied before the
scan at its time, however the scans are run (a step, a run for a time, real
time, a run until a condition), so that a recorded input sequence, such as
the counterexample `ladder verify` found, can be stepped through scan by
scan. A reset starts it again from the first input."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from lang.loader import LD_KIND
from lang.model import Element, Rung, Span
from lang.sim import SimulationError, Simulator
from lang.sim.scenario import Action, Scenario
from lang.sim.uart import messages, show_bytes

from .conditions import Condition, parse_condition
from .document import Document

UART_MESSAGES = 20  # the last messages of the UART a state carries
UART_TAIL = 2048  # the last bytes sent, where they are looked for


class SessionError(ValueError):
    """A command that cannot run; the message is for the user."""


@dataclass(frozen=True)
class Message:
    time_ms: float  # when it began
    text: str


@dataclass(frozen=True)
class Uart:
    sent: int  # bytes
    messages: tuple[Message, ...]  # the last ones, the one under way included


@dataclass(frozen=True)
class Replay:
    """A scenario's inputs, by time, to feed to a simulation."""

    name: str
    actions: tuple[Action, ...]  # in the order of their times
    end_us: int  # the time of the scenario's last scan (its last expectation's)

    @classmethod
    def of(cls, scenario: Scenario) -> Replay:
        return cls(scenario.name, tuple(sorted(scenario.actions, key=lambda a: a.time_us)), scenario.run_until_us)


@dataclass(frozen=True)
class Replaying:
    """How far a replay is."""

    name: str
    applied: int  # inputs applied so far
    total: int
    end_ms: float


@dataclass(frozen=True)
class State:
    time_ms: float
    scan: int
    energized: tuple[Span, ...]  # the glyphs of the elements power flowed out of in the last scan
    values: dict[str, int]
    uart: Uart
    error: str | None
    replay: Replaying | None = None


@dataclass(frozen=True)
class Hint:
    """The values of the names a line shows, left to right, to show after its end."""

    line: int
    col: int
    label: str


D = TypeVar("D", bound=Document)


def _faults(problem: SimulationError) -> str:
    return "; ".join(d.message for d in problem.diagnostics)


class Simulation(Generic[D]):
    def __init__(self, document: D, replay: Replay | None = None):
        """SessionError when the document cannot be simulated; the first scan
        runs (after the replay's inputs at time 0)."""
        if document.has_errors:
            raise SessionError("the program has errors; fix them before simulating")
        try:
            self.sim = Simulator(document.program)
        except SimulationError as problem:
            raise SessionError("cannot simulate: " + _faults(problem)) from problem
        self.document = document  # the version whose program runs, with its positions
        self.error: str | None = None
        self.replay = replay
        self._applied = 0  # the replay's inputs applied so far
        self.step(1)

    def run(self, action: Callable[[], None]) -> None:
        """Run scans; a fault stops them and is kept in `error`."""
        try:
            action()
        except SimulationError as fault:
            self.error = _faults(fault) or str(fault)

    def step(self, cycles: int) -> None:
        self.run(lambda: self._scans(cycles))

    def run_for(self, ms: float) -> None:
        self.run(lambda: self._run_for(ms))

    def _scans(self, cycles: int) -> None:
        """Run scans (a fault raises SimulationError), feeding a replay's inputs before each."""
        while cycles > 0 and self._replaying():
            self._feed()
            self.sim.step(1)
            cycles -= 1
        self.sim.step(cycles)

    def _run_for(self, ms: float) -> None:
        sim = self.sim
        end_us = sim.scan_count * sim.cycle_us + round(ms * 1000)
        while self._replaying() and sim.scan_count * sim.cycle_us < end_us:
            self._scans(1)
        sim.run_for(max(end_us - sim.scan_count * sim.cycle_us, 0) / 1000)

    def _replaying(self) -> bool:
        return self.replay is not None and self._applied < len(self.replay.actions)

    def _feed(self) -> None:
        """Apply the replay's inputs due by the next scan."""
        assert self.replay is not None
        actions, now_us = self.replay.actions, self.sim.scan_count * self.sim.cycle_us
        while self._applied < len(actions) and actions[self._applied].time_us <= now_us:
            action = actions[self._applied]
            self._applied += 1
            try:
                if isinstance(action.value, bytes):
                    self.sim.uart_receive(action.value)
                else:
                    self.sim.set(action.name, action.value)
            except (KeyError, ValueError) as problem:
                self.error = f"the replay of {self.replay.name!r} cannot set {action.name}: {_reason(problem)}"

    def set(self, name: str, value: int) -> None:
        try:
            self.sim.set(name, value)
        except (KeyError, ValueError) as problem:
            raise SessionError(_reason(problem)) from problem

    def toggle(self, name: str) -> None:
        try:
            self.sim.set_input(name, not self.sim.value(name))
        except KeyError as problem:
            raise SessionError(_reason(problem)) from problem

    def reset(self) -> None:
        """Power-on: time 0, no scan run yet; a replay starts again."""
        self.sim.reset(keep_eeprom=True)
        self.error = None
        self._applied = 0

    def value(self, name: str) -> int | None:
        """None for a name the program does not have."""
        try:
            return self.sim.value(name)
        except KeyError:
            return None

    def reload(self, document: D) -> None:
        """Run the program of an edited version, keeping the values; while it
        has errors (or cannot be simulated) the last one keeps running, and
        `error` says so."""
        if document.has_errors:
            self.error = "the edited program has errors; still simulating the last one that read"
            return
        try:
            self.sim.reload(document.program)
        except SimulationError as problem:
            self.error = "the edited program cannot be simulated: " + _faults(problem)
            return
        self.document = document
        self.error = None

    # --- running until a condition holds -------------------------------------------------

    def condition(self, text: str) -> Condition:
        """SessionError for a condition that cannot be read or names what the program lacks."""
        try:
            found = parse_condition(text)
            found.holds(self.sim)
        except ValueError as problem:
            raise SessionError(str(problem)) from problem
        except KeyError as problem:
            raise SessionError(_reason(problem)) from problem
        return found

    def run_until(self, condition: Condition, limit_ms: float, seconds: float) -> bool:
        """Scan until the condition holds, the simulated time reaches
        `limit_ms`, a fault stops it or `seconds` of work have passed;
        whether the condition holds."""
        sim = self.sim
        reached = condition.holds(sim)
        deadline = time.perf_counter() + seconds
        while not reached and sim.time_ms < limit_ms and self.error is None and time.perf_counter() < deadline:
            self.step(1)
            if self.error is not None:
                break
            reached = condition.holds(sim)
        return reached

    # --- what the editor shows ------------------------------------------------------------

    def state(self) -> State:
        sim, document = self.sim, self.document
        energized = []
        rungs = document.program.rungs
        by_rung: dict[int, list[Element]] = {}
        for key, powered in sim.energized().items():
            if not powered or key.rung >= len(rungs):
                continue
            elements = by_rung.get(key.rung)
            if elements is None:
                elements = by_rung[key.rung] = list(rungs[key.rung].elements())
            if key.index >= len(elements):
                continue
            element = elements[key.index]
            if element.span is None:
                continue
            energized.append(element.span if document.kind == LD_KIND else document.locator.glyph_span(element))
        replay = self.replay
        replaying = None if replay is None else \
            Replaying(replay.name, self._applied, len(replay.actions), replay.end_us / 1000)
        return State(float(sim.time_ms), sim.scan_count, tuple(energized), sim.variables(), self.uart(), self.error,
                     replaying)

    def uart(self) -> Uart:
        """How many bytes the UART sent, and its last messages with the time
        each began (the one under way included)."""
        uart = self.sim.peripherals.uart
        recent = uart.sent[-UART_TAIL:]
        found = messages(recent, uart.byte_time_us, self.sim.cycle_us)
        if len(recent) < len(uart.sent):
            found = found[1:]  # it may have begun before the bytes looked at
        return Uart(len(uart.sent), tuple(Message(m.scan_us / 1000, show_bytes(bytes(m.data)))
                                          for m in found[-UART_MESSAGES:]))

    def hints(self, document: Document, first: int, last: int) -> list[Hint]:
        """One hint per line of the rungs between two lines, after its end
        (past the right rail), with the value of each name the line shows,
        left to right: a hint inside the drawing would push the rest of the
        line and break the rails."""
        values = self.sim.variables()
        found: list[Hint] = []
        seen: set[int] = set()  # lines given their hint
        rungs = document.program.rungs
        for rung_first, rung_last, index in document.locator.rung_extents():
            if rung_last < first or rung_first > last:
                continue
            found.extend(_rung_hints(document, rungs[index], first, last, values, seen))
        return found


def _rung_hints(document: Document, rung: Rung, first: int, last: int, values: dict[str, int],
                seen: set[int]) -> list[Hint]:
    by_line: dict[int, dict[int, str]] = {}
    for element in rung.elements():
        for field, span in element.arg_spans.items():
            name = element.args.get(field)
            if first <= span.line <= last and isinstance(name, str) and name in values:
                by_line.setdefault(span.line, {})[span.col] = f"{name}={values[name]}"
    found = []
    for line, shown in sorted(by_line.items()):
        if line in seen:
            continue
        seen.add(line)
        found.append(Hint(line, len(document.line(line)), "  ".join(shown[col] for col in sorted(shown))))
    return found


def _reason(problem: Exception) -> str:
    return str(problem.args[0]) if problem.args else str(problem)
