"""Simulation through `workspace/executeCommand` (docs/lsp-protocol.md):
ladder.sim.start, stop, step, runFor, runRealtime, runUntil, set, toggle,
reset, on one ide.session.Simulation per document. Every command that
changes it answers with the state and pushes a `ladder/simulationState`
notification; in real time the server scans on a timer and pushes at most 10
states a second. Editing the document reloads the program into the running
simulation after the diagnostics delay. While a simulation runs, inlay hints
show the names' values after the end of each line (never inside the drawing).
The state carries what the UART sent: its byte count and its last messages
(lang/sim/uart.py), as `ladder sim --watch uart` prints them, and how far a
replay of recorded inputs is (`start` with a `Replay`: lsp/verify.py's
counterexamples)."""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from lsprotocol import types

from ide.session import Replay, SessionError, Simulation, State

from .documents import Analysis
from .protocol import UserError
from .transport import give_way

if TYPE_CHECKING:
    from .server import LadderServer

NOTIFICATION = "ladder/simulationState"
REALTIME_PERIOD = 0.1  # seconds between real-time scans batches (and notifications)
MAX_CATCH_UP_MS = 1000.0  # a slow machine does not try to catch up more than this
UNTIL_SLICE = 0.02  # seconds of work between two looks at the other requests

Json = dict[str, Any]


class Session:
    def __init__(self, uri: str, simulation: Simulation[Analysis]):
        self.uri = uri
        self.simulation = simulation
        self.realtime = False
        self.task: asyncio.Task[None] | None = None
        self.reload_handle: asyncio.TimerHandle | None = None
        self.busy = False  # a runUntil is under way


class Simulations:
    def __init__(self, server: LadderServer):
        self.server = server
        self.sessions: dict[str, Session] = {}

    def session(self, uri: str) -> Session:
        found = self.sessions.get(uri)
        if found is None:
            raise UserError("no simulation is running for this document: start one with ladder.sim.start")
        return found

    def value_of(self, uri: str, name: str) -> int | None:
        found = self.sessions.get(uri)
        return found.simulation.value(name) if found is not None else None

    def state(self, session: Session | None, uri: str, **extra: object) -> Json:
        if session is None:
            return {"uri": uri, "running": False, "realtime": False, "timeMs": 0.0, "scan": 0,
                    "energized": [], "values": {}, "uart": {"sent": 0, "messages": []}, "error": None,
                    "replay": None, **extra}
        state: State = session.simulation.state()
        positions = session.simulation.document.positions
        return {"uri": uri, "running": True, "realtime": session.realtime, "timeMs": state.time_ms,
                "scan": state.scan, "energized": [_range_json(positions.range(span)) for span in state.energized],
                "values": state.values,
                "uart": {"sent": state.uart.sent,
                         "messages": [{"timeMs": m.time_ms, "text": m.text} for m in state.uart.messages]},
                "error": state.error,
                "replay": None if state.replay is None else {
                    "name": state.replay.name, "applied": state.replay.applied, "total": state.replay.total,
                    "endMs": state.replay.end_ms},
                **extra}

    def publish(self, session: Session | None, uri: str, **extra: object) -> Json:
        state = self.state(session, uri, **extra)
        self.server.notify(NOTIFICATION, state)
        if self.server.client_supports("workspace", "inlay_hint", "refresh_support"):
            try:
                future = self.server.protocol.send_request("workspace/inlayHint/refresh", None)
                future.add_done_callback(lambda f: f.cancelled() or f.exception())  # nothing depends on it
            except Exception:
                pass
        return state

    # --- lifecycle -------------------------------------------------------------------

    def start(self, uri: str, replay: Replay | None = None) -> Json:
        """A new simulation of the document, replaying `replay`'s inputs if given."""
        analysis = self.server.documents.analysis(uri)
        if analysis is None:
            raise UserError("this document is not a ladder program")
        try:
            simulation = Simulation(analysis, replay)
        except SessionError as problem:
            raise UserError(str(problem)) from problem
        self.stop(uri, notify=False)
        session = self.sessions[uri] = Session(uri, simulation)
        return self.publish(session, uri)

    def stop(self, uri: str, notify: bool = True) -> Json:
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
        if analysis is None or analysis is session.simulation.document:
            return
        session.simulation.reload(analysis)
        self.publish(session, uri)

    def schedule_reload(self, uri: str) -> None:
        session = self.sessions.get(uri)
        if session is None:
            return
        if session.reload_handle is not None:
            session.reload_handle.cancel()
        last = self.server.diagnostics.last_duration_ms if self.server.diagnostics is not None else 0.0
        delay = self.server.settings.delay_ms(last) / 1000
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
        simulation = session.simulation
        try:
            while session.realtime and self.sessions.get(session.uri) is session:
                await asyncio.sleep(REALTIME_PERIOD)
                now = loop.time()
                elapsed = min((now - last) * 1000, MAX_CATCH_UP_MS)
                last = now
                if session.busy:
                    continue
                simulation.run_for(elapsed)
                if simulation.error:
                    session.realtime = False
                self.publish(session, session.uri)
        except asyncio.CancelledError:
            pass
        except Exception as problem:
            session.realtime = False
            self.server._failure("real-time simulation", problem)

    async def run_until(self, session: Session, condition_text: str, timeout_ms: float) -> Json:
        simulation = session.simulation
        try:
            condition = simulation.condition(condition_text)
        except SessionError as problem:
            raise UserError(str(problem)) from problem
        limit_ms = simulation.sim.time_ms + timeout_ms
        session.busy = True
        try:
            reached = condition.holds(simulation.sim)
            while not reached and simulation.sim.time_ms < limit_ms and simulation.error is None:
                reached = simulation.run_until(condition, limit_ms, UNTIL_SLICE)
                await give_way(self.server.pipe_writer)  # let other requests (and edits) in
                if self.sessions.get(session.uri) is not session:
                    raise UserError("the simulation was stopped")
        finally:
            session.busy = False
        if session.reload_handle is None and \
                simulation.document is not self.server.documents.analysis(session.uri):
            self.reload(session.uri)
        return self.publish(session, session.uri, reached=reached)


def _range_json(r: types.Range) -> Json:
    return {"start": {"line": r.start.line, "character": r.start.character},
            "end": {"line": r.end.line, "character": r.end.character}}


def _number(value: object, what: str, default: float | None = None, integer: bool = False) -> float:
    if value is None:
        if default is None:
            raise UserError(f"{what} is missing")
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise UserError(f"{what} must be a number, not {value!r}")
    if integer and int(value) != value:
        raise UserError(f"{what} must be a whole number")
    return int(value) if integer else float(value)


def _arg(args: Sequence[object], position: int, key: str) -> object:
    """Positional arguments, or one object with named ones (`{"ms": 100}`)."""
    if len(args) > 1 and isinstance(args[1], dict):
        return args[1].get(key)
    return args[position] if len(args) > position else None


def register(server: LadderServer) -> None:
    sims = server.simulations = Simulations(server)

    def uri_of(args: Sequence[object]) -> str:
        if not args or not isinstance(args[0], str):
            raise UserError("the first argument must be the document's URI")
        return args[0]

    def changing(change: Callable[[Session, Sequence[object]], None]) -> Callable[..., Json]:
        """A command that changes the document's simulation and answers with its state."""
        def run(ls: LadderServer, *args: object) -> Json:
            uri = uri_of(args)
            session = sims.session(uri)
            try:
                change(session, args)
            except SessionError as problem:
                raise UserError(str(problem)) from problem
            return sims.publish(session, uri)
        run.__name__ = change.__name__
        return run

    @server.on_command("ladder.sim.start")
    def start(ls: LadderServer, *args: object) -> Json:
        return sims.start(uri_of(args))

    @server.on_command("ladder.sim.stop")
    def stop(ls: LadderServer, *args: object) -> Json:
        return sims.stop(uri_of(args))

    def step(session: Session, args: Sequence[object]) -> None:
        cycles = int(_number(_arg(args, 1, "cycles"), "cycles", default=1, integer=True))
        if not 0 <= cycles <= 10_000_000:
            raise UserError("cycles must be between 0 and 10000000")
        session.simulation.step(cycles)

    def run_for(session: Session, args: Sequence[object]) -> None:
        ms = _number(_arg(args, 1, "ms"), "ms")
        if not 0 <= ms <= 3_600_000:
            raise UserError("ms must be between 0 and 3600000 (one hour)")
        session.simulation.run_for(ms)

    def run_realtime(session: Session, args: Sequence[object]) -> None:
        on = _arg(args, 1, "on")
        if not isinstance(on, bool):
            raise UserError("on must be true or false")
        sims.set_realtime(session, on)

    def set_value(session: Session, args: Sequence[object]) -> None:
        name = _arg(args, 1, "name")
        value = int(_number(_arg(args, 2, "value"), "value", integer=True))
        if not isinstance(name, str):
            raise UserError("name must be a text")
        session.simulation.set(name, value)

    def toggle(session: Session, args: Sequence[object]) -> None:
        name = _arg(args, 1, "name")
        if not isinstance(name, str):
            raise UserError("name must be a text")
        session.simulation.toggle(name)

    def reset(session: Session, args: Sequence[object]) -> None:
        session.simulation.reset()

    for command, change in (("ladder.sim.step", step), ("ladder.sim.runFor", run_for),
                            ("ladder.sim.runRealtime", run_realtime), ("ladder.sim.set", set_value),
                            ("ladder.sim.toggle", toggle), ("ladder.sim.reset", reset)):
        server.on_command(command)(changing(change))

    @server.on_command("ladder.sim.runUntil")
    async def run_until(ls: LadderServer, *args: object) -> Json:
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

    @server.on(types.TEXT_DOCUMENT_INLAY_HINT)
    def inlay_hints(ls: LadderServer, params: types.InlayHintParams) -> list[types.InlayHint]:
        session = sims.sessions.get(params.text_document.uri)
        if session is None:
            return []
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return []
        hints = session.simulation.hints(analysis, params.range.start.line, params.range.end.line)
        return [types.InlayHint(position=analysis.positions.to_client(h.line, h.col), label=h.label, padding_left=True)
                for h in hints]

    def changed(ls: LadderServer, uri: str | None) -> None:
        if uri in sims.sessions:
            sims.schedule_reload(uri)

    def closed(ls: LadderServer, uri: str | None) -> None:
        if uri in sims.sessions:
            sims.stop(uri, notify=False)

    server.subscribe("changed", changed)
    server.subscribe("closed", closed)
