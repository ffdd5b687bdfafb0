"""A relay between a language client and its server that notes when each
message has crossed the wire: `python benchmarks/wiretap.py LOG SERVER...`
starts the server, passes the client's bytes to it and its bytes back as
they come, and writes one line per complete message to LOG:

    <CLOCK_MONOTONIC seconds> <c2s|s2c> <method or -> <id or -> <version or ->

separated by tabs. A reply's time here is when its last byte reached the
client's side of the pipe, not when the client has parsed it: a Python
client takes about 35 ms to parse the 1.4 MB outline of a 2,000-rung program
(an editor in Node about a tenth of that), and every reply behind it waits
as long. lsp_bench.py gives both figures. Only the first and last bytes of each message are searched,
which is where the client and the server put the id, the method and a
document's version; a message's time is when its last bytes were read, and
the relay's own cost is a few microseconds a message, whatever its size (the
bytes of a message are kept once, not searched again as more come)."""

from __future__ import annotations

import os
import queue
import re
import subprocess
import sys
import threading
import time

HEAD = 400  # bytes at each end of a message searched for its method, id and version
FIELDS = {name: re.compile(rb'"%s":\s*("[^"]*"|-?\d+)' % name.encode()) for name in ("method", "id", "version")}


def _field(head: bytes, tail: bytes, name: str) -> str:
    found = FIELDS[name].search(head) or FIELDS[name].search(tail)
    return found.group(1).decode("latin-1").strip('"') if found else "-"


def relay(source: int, sink: int, direction: str, log, lock: threading.Lock) -> None:
    """Copies bytes from `source` to `sink`, noting each complete message as
    it is read. A thread of its own writes to `sink`, so that a client slow
    to read (a Python one parsing a big reply) does not hold up the reading,
    and so the times, of what the server sends after."""
    outbox: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()

    def deliver() -> None:
        while (chunk := outbox.get()) is not None:
            os.write(sink, chunk)
        os.close(sink)

    writer = threading.Thread(target=deliver, daemon=True)
    writer.start()
    pending = bytearray()  # the bytes of the messages not yet complete
    start = size = 0  # where the first of them has its body, and its length with its header, once that is in
    while chunk := os.read(source, 1 << 16):
        now = time.monotonic()  # when the bytes came: a message's time is that of its last ones
        outbox.put(chunk)
        pending += chunk
        while True:
            if not size:
                end = pending.find(b"\r\n\r\n")
                if end < 0:
                    break
                length = re.search(rb"Content-Length:\s*(\d+)", pending[:end])
                if length is None:  # not a header we understand: nothing more to note
                    pending.clear()
                    break
                start, size = end + 4, end + 4 + int(length.group(1))
            if len(pending) < size:
                break
            head, tail = bytes(pending[start:min(size, start + HEAD)]), bytes(pending[max(start, size - HEAD):size])
            with lock:
                log.write(f"{now:.6f}\t{direction}\t{_field(head, tail, 'method')}\t{_field(head, tail, 'id')}\t"
                          f"{_field(head, tail, 'version')}\n")
            del pending[:size]
            size = 0
    outbox.put(None)
    writer.join()


def main() -> None:
    log_path, command = sys.argv[1], sys.argv[2:]
    server = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, bufsize=0)
    assert server.stdin is not None and server.stdout is not None
    lock = threading.Lock()
    with open(log_path, "w", buffering=1) as log:
        inward = threading.Thread(target=relay, args=(sys.stdin.fileno(), server.stdin.fileno(), "c2s", log, lock),
                                  daemon=True)
        inward.start()
        relay(server.stdout.fileno(), sys.stdout.fileno(), "s2c", log, lock)
        server.wait()
    sys.exit(server.returncode)


if __name__ == "__main__":
    main()
