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
other requests in) is the server's."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from lang.loader import LD_KIND
from lang.model import Element, Rung, Span
from lang.sim import SimulationError, Simulator
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
class State:
    time_ms: float
    scan: int
    energized: tuple[Span, ...]  # the glyphs of the elements power flowed out of in the last scan
    values: dict[str, int]
    uart: Uart
    error: str | None


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
    def __init__(self, document: D):
        """SessionError when the document cannot be simulated; the first scan runs."""
        if document.has_errors:
            raise SessionError("the program has errors; fix them before simulating")
        try:
            self.sim = Simulator(document.program)
        except SimulationError as problem:
            raise SessionError("cannot simulate: " + _faults(problem)) from problem
        self.document = document  # the version whose program runs, with its positions
        self.error: str | None = None
        self.run(lambda: self.sim.step(1))

    def run(self, action: Callable[[], None]) -> None:
        """Run scans; a fault stops them and is kept in `error`."""
        try:
            action()
        except SimulationError as fault:
            self.error = _faults(fault) or str(fault)

    def step(self, cycles: int) -> None:
        self.run(lambda: self.sim.step(cycles))

    def run_for(self, ms: float) -> None:
        self.run(lambda: self.sim.run_for(ms))

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
        self.sim.reset(keep_eeprom=True)
        self.error = None

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
            self.run(lambda: sim.step(1))
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
        return State(float(sim.time_ms), sim.scan_count, tuple(energized), sim.variables(), self.uart(), self.error)

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
