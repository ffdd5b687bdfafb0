"""The wire, made robust: every request gets an answer and a bad frame
costs one message, never the connection.

pygls turns a request whose params do not fit the method (a hover without a
position, `null` or a list for params, a negative position) into an exception
raised while the JSON is read, before it knows which request to answer, so
the client would wait forever; `LadderProtocol` answers it with InvalidParams.
After a frame whose Content-Length is wrong, the rest of the body runs into
the next header and pygls never finds a frame again; `ResyncReader` skips to
the next `Content-Length:` header once a body fails to parse.
"""

from __future__ import annotations

import logging

from pygls.exceptions import JsonRpcException, JsonRpcInvalidRequest
from pygls.protocol import LanguageServerProtocol

log = logging.getLogger("ladder.lsp")
HEADER = b"Content-Length:"


class _Answered:
    """A request already answered with an error while it was read."""


ANSWERED = _Answered()


def _request_id(data: dict) -> int | str | None:
    ident = data.get("id")
    return ident if isinstance(ident, (int, str)) and not isinstance(ident, bool) else None


class LadderProtocol(LanguageServerProtocol):
    def structure_message(self, data):
        try:
            return super().structure_message(data)
        except JsonRpcException as error:
            if "method" not in data or "id" not in data:
                raise  # a notification or a response: nobody waits for an answer
            log.warning("request %r: %s", data.get("method"), error.message)
            self._send_response(_request_id(data), error=error.to_response_error())
            return ANSWERED

    def handle_message(self, message):
        if message is ANSWERED:
            return
        if isinstance(message, dict):
            # JSON without "jsonrpc": not a message; a request-shaped one still gets its answer
            if "method" in message and "id" in message:
                self._send_response(_request_id(message), error=JsonRpcInvalidRequest().to_response_error())
            return
        super().handle_message(message)


class ResyncReader:
    """pygls's reader, which after `lost()` drops input up to the next
    `Content-Length:` header (found anywhere in a line, since the rest of a
    short body runs into it)."""

    def __init__(self, inner):
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

    def readexactly(self, n: int):
        return self.inner.readexactly(n)
