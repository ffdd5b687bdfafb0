"""The whole-document answers made ready after a document opens.

Editors ask for the outline, the semantic tokens and the folding ranges of an
open document, and again after each edit. Each rung's part of those answers
is kept while the rung is unchanged (`Analysis.per_rung`), so an edit costs
only the rungs it changed; the first answer costs every rung, about 250 ms
for 2,000 rungs, and every request behind it would wait as long. So after a
document opens the server works those parts out itself, a few rungs at a
time, and reads every message that has arrived between two slices: a
request or an edit waits one slice at most. Between two slices it also waits
while an answer is being written (`transport.give_way`): the open's own
diagnostics are written by a thread, which the slices kept from running.
Then it joins those parts into the answers' runs of rungs (`Analysis.per_run`)
one run at a time. Before the first slice it makes ready the drawings an
unreadable element's message compares with (`lang.reference.prepare`, about
10 ms): the first edit that left an element unreadable for a moment, as
typing can, waited 30 ms for them."""

from __future__ import annotations

import asyncio
import itertools
from typing import TYPE_CHECKING

from lang import reference

from . import semantic, symbols
from .semantic import encoded_rung
from .symbols import rung_fold, rung_symbol
from .transport import give_way

SLICE = 8  # rungs worked out between two looks at the input: about a millisecond
PARTS = (rung_symbol, encoded_rung, rung_fold)
RUNS = (symbols.runs, semantic.runs)

if TYPE_CHECKING:
    from .server import LadderServer


async def warm(server: LadderServer, uri: str) -> None:
    """Works the parts out on the version opened: the document's results are
    shared by its versions (`RungResults`), so a later version takes those of
    the rungs it kept, and an edit during the warm-up costs neither a new
    read nor a new locator."""
    await give_way(server.pipe_writer)  # the open's diagnostics first
    reference.prepare()
    opened = server.documents.analysis(uri)
    if opened is None:
        return
    extents = opened.locator.rung_extents()
    for done in range(0, len(extents), SLICE):
        await give_way(server.pipe_writer)
        if server.documents.latest(uri) is None:
            return  # closed
        with server.idle.reading():
            for _, _, index in extents[done:done + SLICE]:
                for part in PARTS:
                    part(opened, index)
    await _join_runs(server, uri)


async def _join_runs(server: LadderServer, uri: str) -> None:
    """The answers' runs of those parts joined (lsp/symbols.py, lsp/semantic.py;
    for 18,000 rungs the first outline would join 13 MB in one go), a run at a
    time, on the version read last: again from the start when a newer one is
    read meanwhile (the runs done stay kept for the rungs it kept)."""
    current = server.documents.latest(uri)
    while current is not None:
        for _ in itertools.chain.from_iterable(whole(current) for whole in RUNS):
            await give_way(server.pipe_writer)
            if server.documents.latest(uri) is not current:
                break
        else:
            return
        current = server.documents.latest(uri)


def register(server: LadderServer) -> None:
    tasks: dict[str, asyncio.Future[None]] = {}

    def stop(ls: LadderServer, uri: str | None) -> None:
        assert uri is not None  # a document event
        task = tasks.pop(uri, None)
        if task is not None:
            task.cancel()

    def opened(ls: LadderServer, uri: str | None) -> None:
        assert uri is not None
        stop(ls, uri)
        task = tasks[uri] = asyncio.ensure_future(warm(ls, uri))

        def finished(_: object) -> None:
            if tasks.get(uri) is task:
                del tasks[uri]
            problem = None if task.cancelled() else task.exception()
            if isinstance(problem, Exception):
                ls._failure("the warm-up of the document's answers", problem)

        task.add_done_callback(finished)

    server.subscribe("opened", opened)
    server.subscribe("closed", stop)
