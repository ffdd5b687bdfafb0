"""What every feature module answers with beyond lsprotocol's types: a leaf
module, so that features import it and the server without a cycle."""

from __future__ import annotations

from pygls.exceptions import JsonRpcException


class UserError(JsonRpcException):
    """An error meant for the user (a command that cannot run): answered as an
    LSP error with this message, not logged as a bug."""

    code = -32803  # RequestFailed

    def __init__(self, message: str):
        super().__init__(message=message, code=self.code)


class Raw:
    """A result already in JSON form (dicts, lists, numbers, strings): sent as
    it is, without the converter walking thousands of objects again (document
    symbols and folding of a 2,000-rung program)."""

    __slots__ = ("value",)

    def __init__(self, value: object):
        self.value = value


class Encoded:
    """A result or a notification's params already encoded as JSON text
    (ASCII, as `json.dumps` writes it): put into the message as it is
    (lsp/transport.py), so that a big one assembled from parts kept between
    requests (the document symbols of a 2,000-rung program, 1.5 MB; thousands
    of diagnostics) is not encoded again as a whole."""

    __slots__ = ("text",)

    def __init__(self, text: str):
        self.text = text
