"""Simulation through `workspace/executeCommand` (docs/lsp-protocol.md):
ladder.sim.start, stop, step, runFor, runRealtime, runUntil, set, toggle,
reset. One simulator per document (lang.sim.Simulator); every command that
changes it answers with the state and pushes a `ladder/simulationState`
notification; in real time the server scans on a timer and pushes at most 10
states a second. Editing the document reloads the program into the running
simulator (names that still exist keep their values). While a simulation
runs, inlay hints show the names' values after the end of each line (never inside the drawing).
The state carries what the UART sent: its byte count and its last messages
(lang/sim/uart.py), as `ladder sim --watch uart` prints them.

`set` and `toggle` change a value without running a scan; the next step (or
the real-time timer) shows its effect, as in a PLC whose inputs change
between scans.
"""

from __future__ import annotations

import asyncio
import time

from lsprotocol import types

from ide.conditions import parse_condition
from lang.sim import SimulationError, Simulator
from lang.sim.uart import messages, show_bytes

from .documents import LD
from .protocol import UserError

NOTIFICATION = "ladder/simulationState"
REALTIME_PERIOD = 0.1  # seconds between real-time scans batches (and notifications)
MAX_CATCH_UP_MS = 1000.0  # a slow machine does not try to catch up more than this
UNTIL_SLICE = 0.02  # seconds of work between two looks at the other requests
UART_MESSAGES = 20  # the last messages of the UART a state carries
UART_TAIL = 2048  # the last bytes sent, where they are looked for


class Session:
    def __init__(self, uri: str, analysis, sim: Simulator):
        self.uri = uri
        self.analysis = analysis  # the program the simulator runs, with its positions
        self.sim = sim
        self.realtime = False
        self.task: asyncio.Task | None = None
        self.error: str | None = None
        self.reload_handle: asyncio.TimerHandle | None = None
        self.busy = False  # a runUntil is under way


class Simulations:
    def __init__(self, server):
        self.server = server
        self.sessions: dict[str, Session] = {}

    # --- helpers ---------------------------------------------------------------------

    def session(self, uri: str) -> Session:
        found = self.sessions.get(uri)
        if found is None:
            raise UserError("no simulation is running for this document: start one with ladder.sim.start")
        return found

    def value_of(self, uri: str, name: str) -> int | None:
        found = self.sessions.get(uri)
        if found is None:
            return None
        try:
            return found.sim.value(name)
        except KeyError:
            return None

    def state(self, session: Session | None, uri: str, **extra) -> dict:
        if session is None:
            return {"uri": uri, "running": False, "realtime": False, "timeMs": 0.0, "scan": 0,
                    "energized": [], "values": {}, "uart": {"sent": 0, "messages": []}, "error": None, **extra}
        sim, analysis = session.sim, session.analysis
        energized = []
        rungs = analysis.program.rungs
        by_rung: dict[int, list] = {}
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
            span = element.span if analysis.kind == LD else analysis.locator.glyph_span(element)
            energized.append(_range_json(analysis.positions.range(span)))
        return {"uri": uri, "running": True, "realtime": session.realtime, "timeMs": float(sim.time_ms),
                "scan": sim.scan_count, "energized": energized, "values": sim.variables(),
                "uart": _uart_state(sim), "error": session.error, **extra}

    def publish(self, session: Session | None, uri: str, **extra) -> dict:
        state = self.state(session, uri, **extra)
        self.server.notify(NOTIFICATION, state)
        if self.server.client_supports("workspace", "inlay_hint", "refresh_support"):
            try:
                future = self.server.protocol.send_request("workspace/inlayHint/refresh", None)
                future.add_done_callback(lambda f: f.cancelled() or f.exception())  # nothing depends on it
            except Exception:
                pass
        return state

    def run(self, session: Session, action) -> None:
        """Run scans; a fault is part of the state, not a failed command."""
        try:
            action()
        except SimulationError as fault:
            session.error = "; ".join(d.message for d in fault.diagnostics) or str(fault)

    # --- lifecycle -------------------------------------------------------------------

    def start(self, uri: str) -> dict:
        analysis = self.server.documents.analysis(uri)
        if analysis is None:
            raise UserError("this document is not a ladder program")
        if analysis.has_errors:
            raise UserError("the program has errors; fix them before simulating")
        self.stop(uri, notify=False)
        try:
            sim = Simulator(analysis.program)
        except SimulationError as problem:
            raise UserError("cannot simulate: " + "; ".join(d.message for d in problem.diagnostics)) from problem
        session = self.sessions[uri] = Session(uri, analysis, sim)
        self.run(session, lambda: sim.step(1))
        return self.publish(session, uri)

    def stop(self, uri: str, notify: bool = True) -> dict:
        session = self.sessions.pop(uri, None)
        if session is not None:
            session.realtime = False
            if session.task is not None:
                session.task.cancel()
            if session.reload_handle is not None:
                session.reload_handle.cancel()
        if notify:
            self.publish(None, uri)
        return {}

    def reload(self, uri: str) -> None:
        """The document changed: run the edited program, keeping the values."""
        session = self.sessions.get(uri)
        if session is None:
            return
        session.reload_handle = None
        analysis = self.server.documents.analysis(uri)
        if analysis is None or analysis is session.analysis:
            return
        if analysis.has_errors:
            session.error = "the edited program has errors; still simulating the last one that read"
            self.publish(session, uri)
            return
        try:
            session.sim.reload(analysis.program)
        except SimulationError as problem:
            session.error = "the edited program cannot be simulated: " + "; ".join(
                d.message for d in problem.diagnostics)
            self.publish(session, uri)
            return
        session.analysis = analysis
        session.error = None
        self.publish(session, uri)

    def schedule_reload(self, uri: str) -> None:
        session = self.sessions.get(uri)
        if session is None:
            return
        if session.reload_handle is not None:
            session.reload_handle.cancel()
        delay = self.server.settings.delay_ms(self.server.diagnostics.last_duration_ms) / 1000
        if delay <= 0 and not session.busy:
            self.reload(uri)
            return
        loop = asyncio.get_event_loop()
        session.reload_handle = loop.call_later(max(delay, 0.01), self._reload_safely, uri)

    def _reload_safely(self, uri: str) -> None:
        session = self.sessions.get(uri)
        if session is not None and session.busy:
            self.schedule_reload(uri)  # after the runUntil under way
            return
        try:
            self.reload(uri)
        except Exception as problem:
            self.server._failure("simulation reload", problem)

    # --- real time -------------------------------------------------------------------

    def set_realtime(self, session: Session, on: bool) -> None:
        session.realtime = bool(on)
        if on and (session.task is None or session.task.done()):
            session.task = asyncio.ensure_future(self._realtime(session))
        elif not on and session.task is not None:
            session.task.cancel()
            session.task = None

    async def _realtime(self, session: Session) -> None:
        loop = asyncio.get_running_loop()
        last = loop.time()
        try:
            while session.realtime and self.sessions.get(session.uri) is session:
                await asyncio.sleep(REALTIME_PERIOD)
                now = loop.time()
                elapsed = min((now - last) * 1000, MAX_CATCH_UP_MS)
                last = now
                if session.busy:
                    continue
                self.run(session, lambda elapsed=elapsed: session.sim.run_for(elapsed))
                if session.error:
                    session.realtime = False
                self.publish(session, session.uri)
        except asyncio.CancelledError:
            pass
        except Exception as problem:
            session.realtime = False
            self.server._failure("real-time simulation", problem)

    async def run_until(self, session: Session, condition_text: str, timeout_ms: float) -> dict:
        try:
            condition = parse_condition(condition_text)
        except ValueError as problem:
            raise UserError(str(problem)) from problem
        sim = session.sim
        try:
            reached = condition.holds(sim)
        except KeyError as problem:
            raise UserError(str(problem.args[0]) if problem.args else str(problem)) from problem
        limit_ms = sim.time_ms + timeout_ms
        session.busy = True
        try:
            while not reached and sim.time_ms < limit_ms and session.error is None:
                slice_end = time.perf_counter() + UNTIL_SLICE
                while not reached and sim.time_ms < limit_ms and time.perf_counter() < slice_end:
                    self.run(session, lambda: sim.step(1))
                    if session.error is not None:
                        break
                    reached = condition.holds(sim)
                await asyncio.sleep(0)  # let other requests (and edits) in
                if self.sessions.get(session.uri) is not session:
                    raise UserError("the simulation was stopped")
        finally:
            session.busy = False
        if session.reload_handle is None and session.analysis is not self.server.documents.analysis(session.uri):
            self.reload(session.uri)
        return self.publish(session, session.uri, reached=reached)


def _rung_hints(analysis, rung, first, last, values, seen) -> list[types.InlayHint]:
    """One hint per line, after its end (past the right rail), with the live
    value of each name the line shows, left to right: a hint inside the
    drawing would push the rest of the line and break the rails."""
    by_line: dict[int, dict[int, str]] = {}
    for element in rung.elements():
        for field, span in element.arg_spans.items():
            name = element.args.get(field)
            if first <= span.line <= last and isinstance(name, str) and name in values:
                by_line.setdefault(span.line, {})[span.col] = f"{name}={values[name]}"
    found = []
    for line, names in sorted(by_line.items()):
        if line in seen:
            continue
        seen.add(line)
        found.append(types.InlayHint(
            position=analysis.positions.to_client(line, len(analysis.line(line))),
            label="  ".join(names[col] for col in sorted(names)), padding_left=True))
    return found


def _uart_state(sim: Simulator) -> dict:
    """How many bytes the UART sent, and its last messages with the time
    each began (the one under way included)."""
    uart = sim.peripherals.uart
    recent = uart.sent[-UART_TAIL:]
    found = messages(recent, uart.byte_time_us, sim.cycle_us)
    if len(recent) < len(uart.sent):
        found = found[1:]  # it may have begun before the bytes looked at
    return {"sent": len(uart.sent),
            "messages": [{"timeMs": m.scan_us / 1000, "text": show_bytes(bytes(m.data))}
                         for m in found[-UART_MESSAGES:]]}


def _range_json(r: types.Range) -> dict:
    return {"start": {"line": r.start.line, "character": r.start.character},
            "end": {"line": r.end.line, "character": r.end.character}}


def _number(value, what: str, default=None, integer: bool = False):
    if value is None:
        if default is None:
            raise UserError(f"{what} is missing")
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise UserError(f"{what} must be a number, not {value!r}")
    if integer and int(value) != value:
        raise UserError(f"{what} must be a whole number")
    return int(value) if integer else float(value)


def _arg(args, position: int, key: str):
    """Positional arguments, or one object with named ones (`{"ms": 100}`)."""
    if len(args) > 1 and isinstance(args[1], dict):
        return args[1].get(key)
    return args[position] if len(args) > position else None


def register(server) -> None:
    sims = server.simulations = Simulations(server)

    def uri_of(args) -> str:
        if not args or not isinstance(args[0], str):
            raise UserError("the first argument must be the document's URI")
        return args[0]

    @server.on_command("ladder.sim.start")
    def start(ls, *args):
        return sims.start(uri_of(args))

    @server.on_command("ladder.sim.stop")
    def stop(ls, *args):
        return sims.stop(uri_of(args))

    @server.on_command("ladder.sim.step")
    def step(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        cycles = _number(_arg(args, 1, "cycles"), "cycles", default=1, integer=True)
        if not 0 <= cycles <= 10_000_000:
            raise UserError("cycles must be between 0 and 10000000")
        sims.run(session, lambda: session.sim.step(cycles))
        return sims.publish(session, uri)

    @server.on_command("ladder.sim.runFor")
    def run_for(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        ms = _number(_arg(args, 1, "ms"), "ms")
        if not 0 <= ms <= 3_600_000:
            raise UserError("ms must be between 0 and 3600000 (one hour)")
        sims.run(session, lambda: session.sim.run_for(ms))
        return sims.publish(session, uri)

    @server.on_command("ladder.sim.runRealtime")
    def run_realtime(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        on = _arg(args, 1, "on")
        if not isinstance(on, bool):
            raise UserError("on must be true or false")
        sims.set_realtime(session, on)
        return sims.publish(session, uri)

    @server.on_command("ladder.sim.runUntil")
    async def run_until(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        if session.busy:
            raise UserError("a runUntil is already under way")
        condition = _arg(args, 1, "condition")
        if not isinstance(condition, str):
            raise UserError("condition must be a text such as \"Yred = 1\"")
        timeout = _number(_arg(args, 2, "timeoutMs"), "timeoutMs", default=60000.0)
        if not 0 <= timeout <= 3_600_000:
            raise UserError("timeoutMs must be between 0 and 3600000")
        return await sims.run_until(session, condition, timeout)

    @server.on_command("ladder.sim.set")
    def set_value(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        name = _arg(args, 1, "name")
        value = _number(_arg(args, 2, "value"), "value", integer=True)
        if not isinstance(name, str):
            raise UserError("name must be a text")
        try:
            session.sim.set(name, value)
        except (KeyError, ValueError) as problem:
            raise UserError(str(problem.args[0]) if problem.args else str(problem)) from problem
        return sims.publish(session, uri)

    @server.on_command("ladder.sim.toggle")
    def toggle(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        name = _arg(args, 1, "name")
        if not isinstance(name, str):
            raise UserError("name must be a text")
        try:
            session.sim.set_input(name, not session.sim.value(name))
        except KeyError as problem:
            raise UserError(str(problem.args[0]) if problem.args else str(problem)) from problem
        return sims.publish(session, uri)

    @server.on_command("ladder.sim.reset")
    def reset(ls, *args):
        uri = uri_of(args)
        session = sims.session(uri)
        session.sim.reset(keep_eeprom=True)
        session.error = None
        return sims.publish(session, uri)

    @server.on(types.TEXT_DOCUMENT_INLAY_HINT)
    def inlay_hints(ls, params: types.InlayHintParams):
        session = sims.sessions.get(params.text_document.uri)
        if session is None:
            return []
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return []
        first, last = params.range.start.line, params.range.end.line
        values = session.sim.variables()
        hints = []
        seen: set[int] = set()  # lines given their hint
        rungs = analysis.program.rungs
        for rung_first, rung_last, index in analysis.locator.rung_extents():
            if rung_last < first or rung_first > last:
                continue
            hints.extend(_rung_hints(analysis, rungs[index], first, last, values, seen))
        return hints


    def changed(ls, uri):
        if uri in sims.sessions:
            sims.schedule_reload(uri)

    def closed(ls, uri):
        if uri in sims.sessions:
            sims.stop(uri, notify=False)

    server.subscribe("changed", changed)
    server.subscribe("closed", closed)
