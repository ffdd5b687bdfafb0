"""The language server: pygls wiring only. Every feature lives in its own
module (diagnostics, hover, completion, ...) and registers itself through
`LadderServer.on` / `LadderServer.on_command`, which keep the server alive
whatever a feature does: an exception is logged (stderr and
`window/logMessage`) and answered with an LSP error, and the next request is
served as usual."""

from __future__ import annotations

import asyncio
import logging
import os
import sys
import threading
import traceback
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, BinaryIO, TypeVar, cast

from lsprotocol import types
from pygls.exceptions import JsonRpcContentModified, JsonRpcException, JsonRpcInternalError
from pygls.io_ import StdinAsyncReader, run_async
from pygls.lsp.server import LanguageServer

from .documents import Documents
from .protocol import Raw
from .settings import Settings
from .transport import LadderProtocol, PipeReader, PipeWriter, ResyncReader, widen_pipe

if TYPE_CHECKING:
    from .diagnostics import Publisher
    from .simulation import Simulations
    from .verify import Verifications

log = logging.getLogger("ladder.lsp")

F = TypeVar("F", bound=Callable[..., Any])
# what a feature does on a document event: fn(server, uri)
Listener = Callable[["LadderServer", "str | None"], None]

VERSION = "0.1.0"
# For the robustness tests: LSP methods or command names listed here (comma
# separated) raise inside the feature, as a bug would.
FAULTS_ENV = "LADDER_LSP_FAULTS"


class InjectedFault(RuntimeError):
    pass


class LadderServer(LanguageServer):
    def __init__(self) -> None:
        super().__init__("ladder-lsp", VERSION, text_document_sync_kind=types.TextDocumentSyncKind.Incremental,
                         protocol_cls=LadderProtocol)
        self._reader: ResyncReader | None = None
        # the thread that writes big answers over standard output (None in a browser's worker)
        self.pipe_writer: PipeWriter | None = None
        self.settings = Settings()
        # False in a browser (lsp/worker.py): nothing is written beside the documents
        self.writes_files = True
        self.documents = Documents(self)
        self.protocol._converter.register_unstructure_hook(Raw, lambda raw: raw.value)
        self.faults = {name.strip() for name in os.environ.get(FAULTS_ENV, "").split(",") if name.strip()}
        # the features that hold state, each set by its module's register() (typed services,
        # so that one feature reaches another's through an attribute, not a string key)
        self.diagnostics: Publisher | None = None
        self.simulations: Simulations | None = None
        self.verifications: Verifications | None = None
        self._listeners: dict[str, list[Listener]] = {}
        # requests about one document, answered ContentModified once an edit of it was read
        # after them (lsp/transport.py); each document's revision counts the events that change it
        self.sheddable: set[str] = set()
        self._revisions: dict[str, int] = {}
        from .idle import IdleCollector

        self.idle = IdleCollector()

    # --- document events, shared by the features --------------------------------------

    def subscribe(self, event: str, fn: Listener) -> None:
        """Call `fn(server, uri)` on "opened", "changed", "saved", "closed";
        `fn(server, None)` on "configured"."""
        self._listeners.setdefault(event, []).append(fn)

    def revision(self, uri: str) -> int:
        return self._revisions.get(uri, 0)

    def emit(self, event: str, uri: str | None) -> None:
        self.idle.touch()
        if uri is not None and event in ("opened", "changed", "closed"):
            self._revisions[uri] = self._revisions.get(uri, 0) + 1
        for fn in self._listeners.get(event, ()):
            try:
                fn(self, uri)
            except Exception as problem:  # one feature's bug must not stop the others
                self._failure(f"{event} handler {getattr(fn, '__name__', fn)}", problem)

    # --- registering features ----------------------------------------------------

    def on(self, method: str, options: object = None) -> Callable[[F], F]:
        """Register a feature handler `fn(server, params)`, sync or async."""

        def decorator(fn: F) -> F:
            handler: Callable[[Any], Any]

            def run(params: Any) -> Any:
                self.idle.touch()
                try:
                    self._maybe_fail(method)
                    with self.idle.reading():
                        return fn(self, params)
                except JsonRpcException:
                    raise
                except Exception as problem:
                    raise self._failure(method, problem) from problem

            if asyncio.iscoroutinefunction(fn):
                async def run_async(params: Any) -> Any:
                    self.idle.touch()
                    self._maybe_fail(method)
                    try:
                        return await fn(self, params)
                    except (JsonRpcException, asyncio.CancelledError):
                        raise
                    except Exception as problem:
                        raise self._failure(method, problem) from problem
                handler = run_async
            elif _about_a_document(method):
                self.sheddable.add(method)

                async def run_request(params: Any) -> Any:
                    arrived = cast(LadderProtocol, self.protocol).arrivals.pop(id(params), None)
                    if arrived is not None and self.revision(params.text_document.uri) != arrived:
                        raise JsonRpcContentModified(message="the document changed: ask again")
                    return run(params)
                handler = run_request
            else:
                handler = run
            # no functools.wraps: pygls reads the signature to decide what to pass
            handler.__name__ = fn.__name__
            self.feature(method, options)(handler)
            return fn

        return decorator

    def on_command(self, name: str) -> Callable[[F], F]:
        """Register a `workspace/executeCommand` command `fn(server, *arguments)`."""

        def decorator(fn: F) -> F:
            handler: Callable[..., Any]
            if asyncio.iscoroutinefunction(fn):
                async def run_async(*args: Any) -> Any:
                    self._maybe_fail(name)
                    try:
                        return await fn(self, *args)
                    except (JsonRpcException, asyncio.CancelledError):
                        raise
                    except Exception as problem:
                        raise self._failure(name, problem) from problem
                handler = run_async
            else:
                def run(*args: Any) -> Any:
                    try:
                        self._maybe_fail(name)
                        return fn(self, *args)
                    except JsonRpcException:
                        raise
                    except Exception as problem:
                        raise self._failure(name, problem) from problem
                handler = run
            handler.__name__ = fn.__name__
            self.command(name)(handler)
            return fn

        return decorator

    def _maybe_fail(self, method: str) -> None:
        if method in self.faults:
            raise InjectedFault(f"injected fault in {method}")

    def _failure(self, method: str, problem: Exception) -> JsonRpcInternalError:
        text = "".join(traceback.format_exception(problem))
        log.error("%s failed:\n%s", method, text)
        self.log(f"{method} failed: {problem!r}\n{text}", types.MessageType.Error)
        return JsonRpcInternalError(message=f"{method} failed: {problem}")

    # --- talking to the client ------------------------------------------------------

    def log(self, message: str, kind: types.MessageType = types.MessageType.Log) -> None:
        try:
            self.window_log_message(types.LogMessageParams(type=kind, message=message))
        except Exception:  # no client yet, or the pipe is gone
            log.debug("could not send a log message", exc_info=True)

    def notify(self, method: str, params: object) -> None:
        self.protocol.notify(method, params)

    def report_server_error(self, error: Exception, source: Any) -> None:
        """pygls calls this for a failed notification handler or a message it
        could not read: log it, never pop up a dialog for each keystroke."""
        from pygls.exceptions import FeatureRequestError

        if source is FeatureRequestError:
            return  # already answered with an error (and logged by the feature wrapper)
        if isinstance(error, (ValueError, UnicodeDecodeError)) and self._reader is not None:
            self._reader.lost()  # a body that is no JSON: its frame was cut wrong
        log.error("server error (%s): %s", getattr(source, "__name__", source), error)
        self.log(f"ladder-lsp: {error}", types.MessageType.Error)

    def client_supports(self, *path: str) -> bool:
        """Whether the client declared a capability, e.g.
        client_supports("text_document", "hover", "content_format")."""
        node = getattr(self.protocol, "client_capabilities", None)
        for name in path:
            if node is None:
                return False
            node = getattr(node, name, None)
        return bool(node)


    def start_io(self, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None) -> None:
        """pygls's stdio loop with the resynchronising reader and a writer
        thread (lsp/transport.py)."""
        self._stop_event = threading.Event()
        stdin = stdin or sys.stdin.buffer
        self._reader = ResyncReader(PipeReader(stdin, StdinAsyncReader(stdin, self.thread_pool)))
        stdout = stdout or sys.stdout.buffer
        widen_pipe(stdout)
        writer = self.pipe_writer = PipeWriter(stdout)
        self.protocol.set_writer(writer)
        try:
            asyncio.run(run_async(stop_event=self._stop_event, reader=self._reader, protocol=self.protocol,
                                  logger=log, error_handler=self.report_server_error))
        except (KeyboardInterrupt, SystemExit):
            pass
        finally:
            self.shutdown()  # type: ignore[no-untyped-call]  # pygls 2 does not annotate it
            writer.close()


def _about_a_document(method: str) -> bool:
    """A request (not a notification) whose params name a text document."""
    kinds = types.METHOD_TO_TYPES.get(method)
    if kinds is None or kinds[1] is None:
        return False
    return any(field.name == "text_document" for field in getattr(kinds[2], "__attrs_attrs__", ()))


def create_server() -> LadderServer:
    from . import (
        actions,
        completion,
        convert,
        diagnostics,
        formatting,
        hover,
        lifecycle,
        navigation,
        semantic,
        simulation,
        symbols,
        verify,
        warmup,
    )

    server = LadderServer()
    for module in (lifecycle, diagnostics, hover, formatting, completion, navigation, symbols, semantic,
                   actions, convert, simulation, verify, warmup):
        module.register(server)
    return server


def main(log_file: str | None = None, verbose: bool = False) -> int:
    level = logging.DEBUG if verbose else logging.WARNING
    if log_file:
        logging.basicConfig(filename=log_file, level=level, format="%(asctime)s %(name)s %(levelname)s %(message)s")
    else:
        logging.basicConfig(level=level, format="%(name)s %(levelname)s %(message)s")
    if not verbose:
        # pygls logs every message it sends at INFO: keep that out of stderr
        logging.getLogger("pygls").setLevel(logging.WARNING)
    server = create_server()
    server.start_io()
    return 0
