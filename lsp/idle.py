"""Garbage collection out of the way of typing.

A large program keeps about a million objects alive (rungs, elements, spans,
the reader's cache, the index): 18,000 rungs are a million objects, and a
full collection walks them all, 0.6 to 1.5 s on this kind of machine, for a
few hundred objects of cyclic garbage (an open and 60 edits of that program
left 462). Acyclic garbage, nearly all of it, is freed at once by reference
counting, collected or not.

So the server never walks the whole heap while the user may be typing:

* the automatic full collections are off (the third threshold; Python 3.14's
  incremental collector, Pyodide's in the browser, ignores it and collects
  the old generation a slice at a time); young generations are still
  collected automatically (they hold only what was made lately);
* nothing is collected while a document is read and checked, or a request
  answered, and what exists then is frozen (`gc.freeze`: moved out of the
  generations the collector walks, a constant-time step);
* after a second of quiet the server collects what was made since the last
  freeze (a few thousand objects a version: about a millisecond) and freezes
  what survives;
* during a long burst of edits, once a few young collections have passed,
  what survived them is frozen without being walked (a constant-time step):
  collecting it while the client types cost up to a second in the storm of
  `benchmarks/lsp_bench.py` on 18,000 rungs (the warm-up's parts and the
  rungs a line added had moved, a million objects), and acyclic garbage
  among it is freed by reference counting all the same;
* the whole heap is walked (unfrozen, collected, frozen again) only when it
  can hold much garbage, after a document was closed or many edits were
  made, and only once the client has been quiet for `FULL_QUIET_S`.

`pauses` keeps how long each collection took, and whether the client was
quiet then (tests, benchmarks): while it types, none."""

from __future__ import annotations

import asyncio
import gc
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

QUIET_S = 1.0  # collect what is new once the client has been quiet this long
FULL_QUIET_S = 10.0  # walk the whole heap only after this long a quiet
CHECK_EVERY_S = 0.5
# young collections since the last freeze after which their survivors are frozen even if the
# client is busy: what a quiet collection walks stays small (20: about 140,000 objects at most)
MAX_DEFERRED = 20
FULL_AFTER_EDITS = 5_000  # events (edits...) after which the whole heap is worth walking


class IdleCollector:
    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self.clock = clock
        self.last_activity = clock()
        self.task: asyncio.Task[None] | None = None
        self.collections = 0
        self.dirty = False  # events since the last collection
        self.events = 0  # since the whole heap was last walked
        self.full_due = False
        self.pauses: list[tuple[float, bool, bool]] = []  # (ms, whole heap, client quiet)

    def start(self) -> None:
        if self.task is not None:
            return
        gc.set_threshold(gc.get_threshold()[0], gc.get_threshold()[1], 1_000_000_000)
        self.task = asyncio.ensure_future(self._run())

    @contextmanager
    def reading(self) -> Iterator[None]:
        """No collection while the server reads, checks or answers for a
        document: what that makes mostly lives as long as the version (a
        line added above 9,000 rungs makes 9,000 new ones), and walking it
        again and again as it grows cost 73 young collections, a third of
        that edit's time on 18,000 rungs; what it leaves is frozen (a
        constant-time step). Nested, the outermost decides."""
        if not gc.isenabled():
            yield
            return
        gc.disable()
        try:
            yield
        finally:
            gc.enable()
            gc.freeze()

    def touch(self) -> None:
        self.last_activity = self.clock()
        self.dirty = True
        self.events += 1

    def released(self) -> None:
        """A document was closed: its objects may be held by cycles among
        frozen ones, which only a walk of the whole heap frees."""
        self.full_due = True

    def step(self) -> None:
        """One look: collect what is due, as the quiet allows."""
        quiet_for = self.clock() - self.last_activity
        if quiet_for >= FULL_QUIET_S and (self.full_due or self.events >= FULL_AFTER_EDITS):
            self._collect(whole=True, quiet=True)
            self.full_due, self.events = False, 0
        elif quiet_for >= QUIET_S and self.dirty:
            self._collect(whole=False, quiet=True)
        elif gc.get_count()[2] > MAX_DEFERRED:
            gc.freeze()  # resets the counts

    def _collect(self, whole: bool, quiet: bool) -> None:
        start = time.perf_counter()
        if whole:
            gc.unfreeze()
        gc.collect()
        gc.freeze()
        self.pauses.append(((time.perf_counter() - start) * 1000, whole, quiet))
        del self.pauses[:-100]
        self.collections += 1
        self.dirty = False

    async def _run(self) -> None:
        try:
            while True:
                await asyncio.sleep(CHECK_EVERY_S)
                self.step()
        except asyncio.CancelledError:
            pass
