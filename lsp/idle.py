"""Garbage collection out of the way of typing.

A large program keeps about a million objects alive (rungs, elements, spans,
the reader's cache); each analysis creates tens of thousands more that live
long enough to reach Python's oldest generation, so a full collection (50 to
100 ms for 2,000 rungs) would otherwise fall in the middle of some keystroke's
analysis every few edits. The server turns off the automatic full collections
and runs them itself when the client has been quiet for a moment, or when too
many have been put off. Young generations are still collected automatically;
acyclic garbage (most of it) is freed at once by reference counting anyway.

After each collection, and once a document is read, the objects that survived
are frozen (`gc.freeze`: moved out of the generations the collector walks, a
constant-time step), so a collection that cannot wait for a quiet moment —
during a long burst of edits — walks only what was made since, not the whole
program; the quiet one unfreezes them first and walks everything."""

from __future__ import annotations

import asyncio
import gc
import time
from contextlib import contextmanager

QUIET_S = 1.0  # collect once the client has been quiet this long
CHECK_EVERY_S = 0.5
MAX_DEFERRED = 400  # young collections since the last full one: collect even if busy


class IdleCollector:
    def __init__(self):
        self.last_activity = time.monotonic()
        self.task: asyncio.Task | None = None
        self.collections = 0
        self.dirty = False

    def start(self) -> None:
        if self.task is not None:
            return
        gc.set_threshold(gc.get_threshold()[0], gc.get_threshold()[1], 1_000_000_000)
        self.task = asyncio.ensure_future(self._run())

    @contextmanager
    def reading(self):
        """No collection while a whole document is read and checked: what
        that makes lives as long as the document, and walking it again and
        again as it grows would cost a tenth of the work; what it leaves
        exists from then on and is frozen."""
        gc.disable()
        try:
            yield
        finally:
            gc.enable()
            gc.freeze()

    def touch(self) -> None:
        self.last_activity = time.monotonic()
        self.dirty = True

    async def _run(self) -> None:
        try:
            while True:
                await asyncio.sleep(CHECK_EVERY_S)
                quiet = time.monotonic() - self.last_activity >= QUIET_S
                if (quiet and self.dirty) or gc.get_count()[2] > MAX_DEFERRED:
                    if quiet:
                        gc.unfreeze()
                    gc.collect()
                    gc.freeze()
                    self.collections += 1
                    self.dirty = False
        except asyncio.CancelledError:
            pass
