"""The language server without a process: in a Web Worker on Pyodide (the
playground page, web/; a web extension), or wherever messages arrive one
whole JSON-RPC message at a time.

A browser gives a worker no standard input, no threads and no blocking
event loop: `asyncio.run` and pygls's `start_io` fail there ("WebAssembly
stack switching not supported"). So nothing here reads or waits. The
worker's script calls `Connection.receive` with each message's JSON as it
arrives (`onmessage`), the server handles it at once, and every answer and
notification goes out through `post` (`postMessage`), also as one whole
message's JSON, without LSP's Content-Length headers. What the server does
later (the diagnostics delay, real-time simulation, the warm-up of the
answers) is scheduled on the running event loop, which on Pyodide is the
browser's own (timers and promises).

Nothing is written to disk in a browser (`LadderServer.writes_files`):
`ladder.convert`, `ladder.build` and compile on save say so, and
`ladder.export` (lsp/worker_files.py) answers with the files' contents
instead, to download or open in an editor."""

from __future__ import annotations

import json
import logging
from collections.abc import Callable

from pygls.exceptions import JsonRpcException

from .server import LadderServer, create_server

log = logging.getLogger("ladder.lsp")

Post = Callable[[str], None]


class PostWriter:
    """pygls's writer: each message's JSON, as text, to `post`."""

    def __init__(self, post: Post) -> None:
        self.post = post

    def write(self, data: bytes) -> None:
        self.post(data.decode("utf-8"))

    def close(self) -> None:
        """The page owns the channel: nothing to close here."""


class Connection:
    """One client's server, fed message by message."""

    def __init__(self, post: Post) -> None:
        from . import worker_files

        self.server: LadderServer = create_server()
        self.server.writes_files = False
        worker_files.register(self.server)
        self.server.protocol.set_writer(PostWriter(post), include_headers=False)

    def receive(self, text: str) -> None:
        """Handle one message (its JSON text); a message that is no JSON is
        logged and dropped, as a bad frame is on standard input."""
        protocol = self.server.protocol
        try:
            message = json.loads(text, object_hook=protocol.structure_message)
            protocol.handle_message(message)
        except Exception as problem:
            log.exception("could not handle a message")
            self.server.report_server_error(problem, JsonRpcException)


def connect(post: Post) -> Callable[[str], None]:
    """A new server whose messages go to `post`; returns what takes the client's."""
    return Connection(post).receive
