"""What the UART sent, written for people: bytes as a scenario file writes
them (`"OK\\r\\n"`), grouped into messages. `ladder sim --watch uart`, its
plot and the editor's simulation view all show the same messages.

A message is what a serial terminal would show as one burst: bytes the
program sent back to back (each starting no later than one cycle after the
frame before it ended), up to and including a line end (`\\n`), and at most
a terminal line's 80 bytes, so that a stream that never ends a line still
shows as it goes. A program that sends one character every half second so
shows one message a character; a FORMATTED_STRING, which sends a character
a scan, shows its whole text.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

# the escapes a scenario string takes, besides \xHH
ESCAPES = {"n": "\n", "r": "\r", "t": "\t", "\\": "\\", '"': '"', "0": "\0", "e": "\x1b"}
_SHOWN = {ord(text): f"\\{key}" for key, text in ESCAPES.items() if key not in "\\\""}
_SHOWN.update({ord("\\"): "\\\\", ord('"'): '\\"'})
MESSAGE_BYTES = 80  # the longest message


def show_bytes(data: bytes) -> str:
    """Bytes as a scenario file writes them (`"OK\\r\\n"`), or `nothing`."""
    if not data:
        return "nothing"
    return '"' + "".join(_SHOWN.get(b) or (chr(b) if 32 <= b < 127 else f"\\x{b:02X}") for b in data) + '"'


@dataclass(frozen=True)
class SentByte:
    scan_us: int  # the time of the scan that wrote it
    start_us: float  # its frame's start: later than the scan when it waited for the byte before
    byte: int


@dataclass
class Message:
    scan_us: int  # the scan that sent its first byte
    end_us: float  # when its last frame ends
    data: bytearray = field(default_factory=bytearray)


class Messages:
    """Groups bytes into messages as they are sent: `add` and `idle` return
    the messages that are complete."""

    def __init__(self, byte_time_us: float, cycle_us: int):
        self.byte_time_us = byte_time_us
        self.cycle_us = cycle_us
        self.open: Message | None = None

    def add(self, sent: SentByte) -> list[Message]:
        done = []
        if self.open is not None and sent.start_us > self.open.end_us + self.cycle_us:
            done.append(self.open)
            self.open = None
        if self.open is None:
            self.open = Message(sent.scan_us, 0.0)
        self.open.data.append(sent.byte)
        self.open.end_us = sent.start_us + self.byte_time_us
        if sent.byte == ord("\n") or len(self.open.data) == MESSAGE_BYTES:
            done.append(self.open)
            self.open = None
        return done

    def idle(self, next_scan_us: int) -> list[Message]:
        """The open message, once no byte of the scan at `next_scan_us` or
        later can join it."""
        if self.open is not None and next_scan_us > self.open.end_us + self.cycle_us:
            done, self.open = self.open, None
            return [done]
        return []

    def close(self) -> list[Message]:
        done, self.open = self.open, None
        return [done] if done is not None else []


def messages(sent: Iterable[SentByte], byte_time_us: float, cycle_us: int) -> list[Message]:
    """Every message of `sent`, the last one whether complete or not."""
    grouping = Messages(byte_time_us, cycle_us)
    found = [message for byte in sent for message in grouping.add(byte)]
    return found + grouping.close()
