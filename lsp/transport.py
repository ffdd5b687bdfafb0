"""The wire, made robust: every request gets an answer and a bad frame
costs one message, never the connection.

pygls turns a request whose params do not fit the method (a hover without a
position, `null` or a list for params, a negative position) into an exception
raised while the JSON is read, before it knows which request to answer, so
the client would wait forever; `LadderProtocol` answers it with InvalidParams.
After a frame whose Content-Length is wrong, the rest of the body runs into
the next header and pygls never finds a frame again; `ResyncReader` skips to
the next `Content-Length:` header once a body fails to parse.

A request about a document that an edit read after it has made stale is
answered ContentModified instead of being worked out (as rust-analyzer does):
while the client types faster than the server answers, the work queued up is
dropped instead of growing. For that the server must see the edits that
arrived after a request before it works the request out: `PipeReader` reads
standard input in the event loop, so every message that has arrived is read,
one after the other, before any request's handler runs (pygls's reader hands
each line to a thread, which lets handlers run between two messages), and
`LadderProtocol` notes, as it reads a request, which revision of its
document it was made on (`LadderServer.on` compares when it runs).

A big answer is written by a thread of its own (`PipeWriter`): the outline
of 18,000 rungs is 13 MB, which the client reads 64 KB at a time, and while
the server's one thread waited for it (60-200 ms on a loaded machine) no
message was read and no answer worked out. Work the server does in the
background, a slice at a time, gives that thread its turn (`give_way`).
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import inspect
import json
import logging
import os
import queue
import stat
import sys
import threading
from collections.abc import Awaitable, Generator
from typing import IO, TYPE_CHECKING, Any, BinaryIO, cast

from lsprotocol import types
from pygls.exceptions import JsonRpcContentModified, JsonRpcException, JsonRpcInvalidRequest
from pygls.protocol import JsonRPCResponseMessage, LanguageServerProtocol, lsp_method

from .protocol import Encoded, UserError
from .text import LineWorkspace

if TYPE_CHECKING:
    from pygls.io_ import AsyncReader
    from pygls.protocol.json_rpc import MsgId, RPCMessage

    from .server import LadderServer

log = logging.getLogger("ladder.lsp")
HEADER = b"Content-Length:"


class _Answered:
    """A request already answered with an error while it was read."""


ANSWERED = _Answered()


def _request_id(data: dict[str, Any]) -> int | str | None:
    ident = data.get("id")
    return ident if isinstance(ident, (int, str)) and not isinstance(ident, bool) else None


class LadderProtocol(LanguageServerProtocol):
    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        # id(params) of a request read, not yet worked out -> the revision of its document then
        self.arrivals: dict[int, int] = {}

    @lsp_method(types.INITIALIZE)
    def lsp_initialize(self, params: types.InitializeParams) -> Generator[Any, Any, Any]:
        result = yield from super().lsp_initialize(params)
        # documents kept as lines, an edit changing the lines it touches (lsp/text.py)
        if self._workspace is not None:
            self._workspace = LineWorkspace.like(self._workspace)
        return result

    @lsp_method(types.SHUTDOWN)
    def lsp_shutdown(self, *args: Any) -> Generator[Any, Any, None]:
        # pygls cancels the pending requests while iterating over the table that a
        # cancelled request's answer removes it from ("dictionary changed size during
        # iteration": the shutdown was answered with an error): cancel them first, from a copy
        current = self.msg_id
        for msg_id, future in list(self._request_futures.items()):
            if msg_id != current and not future.done():
                future.cancel()
        return (yield from super().lsp_shutdown(*args))

    def _send_handler_result(self, future: concurrent.futures.Future[Any], *, msg_id: MsgId) -> None:
        # pygls logs every error answer with a traceback: not these, which are answers, not bugs
        expected = not future.cancelled() and isinstance(future.exception(), (JsonRpcContentModified, UserError))
        if not expected:
            super()._send_handler_result(future, msg_id=msg_id)
            return
        self._request_futures.pop(msg_id, None)
        self._send_response(msg_id, error=cast(JsonRpcException, future.exception()).to_response_error())

    def _send_data(self, data: Any) -> None:
        result, params = getattr(data, "result", None), getattr(data, "params", None)
        if self.writer is None:
            super()._send_data(data)
            return
        if isinstance(data, JsonRPCResponseMessage) and isinstance(result, Encoded):
            head, text = f'{{"id": {json.dumps(data.id)}, "jsonrpc": "2.0", "result": ', result.text
        elif isinstance(params, Encoded):  # a notification
            head, text = f'{{"method": {json.dumps(data.method)}, "jsonrpc": "2.0", "params": ', params.text
        else:
            super()._send_data(data)
            return
        # the body's parts encoded apart and joined once: the outline of 18,000 rungs is 13 MB,
        # and each copy of it costs milliseconds
        parts = [head.encode(self.CHARSET), text.encode(self.CHARSET), b"}"]
        if self._include_headers:  # a worker's messages are whole already (lsp/worker.py)
            length = sum(map(len, parts))
            parts.insert(0, f"Content-Length: {length}\r\nContent-Type: {self.CONTENT_TYPE}; "
                            f"charset={self.CHARSET}\r\n\r\n".encode(self.CHARSET))
        written = self.writer.write(b"".join(parts))
        if inspect.isawaitable(written):
            asyncio.ensure_future(written)

    def structure_message(self, data: dict[str, Any]) -> Any:
        try:
            return super().structure_message(data)
        except JsonRpcException as error:
            if "method" not in data or "id" not in data:
                raise  # a notification or a response: nobody waits for an answer
            log.warning("request %r: %s", data.get("method"), error.message)
            # an error answer's id is null when the request's is unreadable (JSON-RPC); pygls's MsgId leaves None out,
            # the ResponseErrorMessage it builds takes it
            self._send_response(_request_id(data), error=error.to_response_error())  # type: ignore[arg-type]
            return ANSWERED

    def handle_message(self, message: RPCMessage | dict[str, Any] | _Answered) -> None:
        if isinstance(message, _Answered):
            return
        if isinstance(message, dict):
            # JSON without "jsonrpc": not a message; a request-shaped one still gets its answer
            if "method" in message and "id" in message:
                self._send_response(_request_id(message),  # type: ignore[arg-type]  # a null id, as above
                                    error=JsonRpcInvalidRequest().to_response_error())
            return
        params = getattr(message, "params", None)
        document = getattr(params, "text_document", None)
        server = cast("LadderServer", self._server)
        if document is not None and getattr(message, "id", None) is not None \
                and getattr(message, "method", None) in server.sheddable:
            self.arrivals[id(params)] = server.revision(document.uri)
        super().handle_message(message)


class ResyncReader:
    """pygls's reader, which after `lost()` drops input up to the next
    `Content-Length:` header (found anywhere in a line, since the rest of a
    short body runs into it)."""

    def __init__(self, inner: AsyncReader):
        self.inner = inner
        self._lost = False

    def lost(self) -> None:
        self._lost = True

    async def readline(self) -> bytes:
        line = await self.inner.readline()
        while self._lost and line:
            at = line.find(HEADER)
            if at >= 0:
                self._lost = False
                return line[at:]
            line = await self.inner.readline()
        return line

    def readexactly(self, n: int) -> Awaitable[bytes]:
        return self.inner.readexactly(n)


def _pollable(stdin: IO[bytes]) -> bool:
    """Whether the event loop can watch `stdin`: a pipe or a socket. asyncio
    also takes a character device, but epoll refuses some (/dev/null), and
    only inside a callback, where the failure cannot be caught: the server
    would wait forever on input that has ended."""
    try:
        mode = os.fstat(stdin.fileno()).st_mode
    except (ValueError, OSError, AttributeError):  # no file descriptor
        return False
    return stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode)


class PipeReader:
    """Standard input read by the event loop (a pipe: what an editor gives a
    language server), so that reading every message already arrived never
    lets a handler run in between; `fallback` (pygls's reader) for anything
    else."""

    def __init__(self, stdin: IO[bytes], fallback: AsyncReader):
        self.stdin = stdin
        self.fallback = fallback
        self._stream: asyncio.StreamReader | None = None
        self._tried = False

    async def _source(self) -> asyncio.StreamReader | None:
        if not self._tried:
            self._tried = True
            if not _pollable(self.stdin):
                return None
            stream = asyncio.StreamReader(limit=1 << 30)  # a lost frame's body is read as one line
            await asyncio.get_running_loop().connect_read_pipe(lambda: asyncio.StreamReaderProtocol(stream), self.stdin)
            self._stream = stream
        return self._stream

    async def readline(self) -> bytes:
        stream = await self._source()
        if stream is None:
            return await self.fallback.readline()
        return await stream.readline()

    async def readexactly(self, n: int) -> bytes:
        stream = await self._source()
        if stream is None:
            return await self.fallback.readexactly(n)
        try:
            return await stream.readexactly(n)
        except asyncio.IncompleteReadError as cut:
            return cut.partial


WRITER_TURN_S = 0.001  # how long background work sleeps while the writer thread has an answer to write
PIPE_BYTES = 1 << 20  # Linux's largest pipe an unprivileged process may ask for
SMALL_BYTES = 1 << 16  # an answer this small is written at once when none waits: a pipe's least room


def widen_pipe(stream: IO[bytes]) -> None:
    """Asks for a 1 MB pipe rather than 64 KB (Linux), so that a big answer
    crosses in a dozen turns of the client rather than 200; anything else
    (a file, another system, a refusal) is left as it is."""
    if sys.platform != "linux":
        return
    import fcntl  # POSIX only

    try:
        if stat.S_ISFIFO(os.fstat(stream.fileno()).st_mode):
            fcntl.fcntl(stream.fileno(), fcntl.F_SETPIPE_SZ, PIPE_BYTES)
    except (OSError, ValueError, AttributeError):  # no descriptor, or more than this user may have
        log.debug("the pipe keeps its size", exc_info=True)


class PipeWriter:
    """pygls's writer interface over a stream, for answers that may not fit
    the pipe: a big answer is handed to a thread of its own, and the event
    loop goes on reading and answering while the client takes it; what is
    written after it waits its turn on that thread. A small answer with none
    waiting is written at once, as before (through a thread, each would
    cost two handovers of the interpreter's lock). `close` waits until
    everything handed over is written (the answer to shutdown before exit).
    Once the client is gone, what is left is dropped."""

    def __init__(self, stream: BinaryIO):
        self._stream = stream
        self._pending: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()
        self._lock = threading.Lock()
        self._waiting = 0  # messages handed to the thread, not written yet
        self._gone = False
        self._thread = threading.Thread(target=self._run, name="ladder-lsp-writer", daemon=True)
        self._thread.start()

    @property
    def busy(self) -> bool:
        """Whether an answer handed to the thread is not written yet."""
        return self._waiting > 0

    def write(self, data: bytes) -> None:
        with self._lock:
            if self._waiting or len(data) > SMALL_BYTES:
                self._waiting += 1
                self._pending.put(data)
                return
            self._send(data)

    def _send(self, data: bytes) -> None:
        if self._gone:
            return
        try:
            self._stream.write(data)
            self._stream.flush()
        except (OSError, ValueError):  # a broken pipe, a closed stream: the client is gone
            self._gone = True
            log.error("the client closed the connection")

    def _run(self) -> None:
        while (data := self._pending.get()) is not None:
            self._send(data)
            with self._lock:
                self._waiting -= 1

    def close(self) -> None:
        self._pending.put(None)
        self._thread.join()
        try:
            self._stream.close()
        except (OSError, ValueError):
            log.debug("standard output was closed already", exc_info=True)


async def give_way(writer: PipeWriter | None) -> None:
    """Lets the rest run between two slices of background work: the event
    loop's callbacks, then the writer thread until it has written what it was
    handed. `asyncio.sleep(0)` alone starves that thread: the event loop lets
    the interpreter's lock go for a zero-timeout poll and takes it back within
    microseconds, and a thread woken on another CPU finds it taken again, while
    its 5 ms request to have it handed over is dropped each time the lock
    changes hands (CPython's GIL). The diagnostics of an open (117 KB for 505
    diagnostics, so written by the thread) then reached the client only after
    the whole warm-up, 170-210 ms later, in a fifth to three quarters of the
    opens of a run (docs/lsp.md, "Opens"). A real sleep leaves the lock to the
    thread."""
    await asyncio.sleep(0)
    while writer is not None and writer.busy:
        await asyncio.sleep(WRITER_TURN_S)
