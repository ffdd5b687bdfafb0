"""The language server's per-rung results (lsp/documents.py RungResults) and
its garbage collection (lsp/idle.py), in process: what the LSP tests cannot
see from outside."""

from __future__ import annotations

import gc
from types import SimpleNamespace

import pytest

from ide.analysis import RUN, RungResults
from ide.analysis import still_moved as _still_moved
from lang.model import Element, Program, Rung, Series
from lsp.idle import IdleCollector


def rung(name: str) -> Rung:
    return Rung(Series([Element("CONTACTS", {"name": name, "negated": 0, "set1": 0})]))


def test_a_moved_rung_takes_its_old_result_shifted_when_first_asked():
    results = RungResults({"lines": lambda value, delta: value + delta})
    old = rung("Xa")
    assert results.get("lines", old, None, lambda: 10) == 10
    moved = rung("Xa")
    asked = []
    assert results.get("lines", moved, (old, 3), lambda: asked.append(1) or 0) == 13
    assert results.get("lines", moved, None, lambda: asked.append(1) or 0) == 13  # kept
    assert asked == []
    # a feature that cannot shift its result works it out again
    assert results.get("other", moved, (old, 3), lambda: 7) == 7


def test_moves_compose_across_versions_no_feature_looked_at():
    first, second, third = rung("Xa"), rung("Xa"), rung("Xa")
    kept = rung("Xb")
    earlier = _still_moved({}, Program(rungs=[second, kept]), {id(second): (first, 2)})
    # the next version moves `second` again and keeps `kept` as it was
    later = _still_moved(earlier, Program(rungs=[third, kept]), {id(third): (second, -1)})
    assert later == {id(third): (first, 1)}


def test_results_of_rungs_gone_are_dropped_once_there_are_many():
    results = RungResults({})
    live, origin = rung("Xa"), rung("Xo")
    results.get("f", origin, None, lambda: 1)
    results.get("f", live, None, lambda: 2)
    dead = [rung(f"X{n}") for n in range(RungResults.SLACK * 110)]
    for each in dead:
        results.get("f", each, None, lambda: 0)
    moved = rung("Xm")
    results.prune(Program(rungs=[live, moved]), {id(moved): (origin, 1)})
    assert set(results.values) == {("f", id(live)), ("f", id(origin))}


def test_no_collection_while_a_document_is_read_and_what_it_made_is_frozen():
    collector = IdleCollector()
    gc.unfreeze()
    before = gc.get_freeze_count()
    try:
        with pytest.raises(RuntimeError):
            with collector.reading():
                assert not gc.isenabled()
                made = [[n] for n in range(1000)]
                raise RuntimeError("a reader's bug")
        assert gc.isenabled()
        assert gc.get_freeze_count() >= before + len(made)
    finally:
        gc.unfreeze()


def opened_document(rungs: int, pipe_writer=None):
    """A document of `rungs` rungs read and held as the server holds an open
    one, and a stand-in for the server around it."""
    from pygls.workspace import PositionCodec
    from test_lsp_incremental import big_text

    from ide.incremental import IncrementalReader
    from lsp.documents import LADDER, Analysis

    text = big_text(rungs)
    reader = IncrementalReader("ladder")
    program, problems = reader.read(text)
    analysis = Analysis("file:///w.ladder", 1, LADDER, text, program, problems, PositionCodec())
    analysis.split = reader.split()
    open_ = {"file:///w.ladder": analysis}
    server = SimpleNamespace(documents=SimpleNamespace(analysis=open_.get, latest=open_.get), idle=IdleCollector(),
                             pipe_writer=pipe_writer)
    return analysis, server


def test_the_warm_up_works_every_rung_out_and_lets_messages_in_between():
    import asyncio

    from lsp import warmup

    analysis, server = opened_document(200)
    seen = []

    async def run():
        task = asyncio.ensure_future(warmup.warm(server, "file:///w.ladder"))
        while not task.done():  # a message handled between two slices
            seen.append(len(analysis.memo.values))
            await asyncio.sleep(0)
        await task

    asyncio.run(run())
    rungs = len(analysis.program.rungs)
    done = 4 * rungs  # symbol, tokens (and encoded), fold
    assert rungs == 200 and len(analysis.memo.values) == done
    assert len([n for n in seen if n < done]) > rungs // warmup.SLICE
    # then the answers' runs of those parts (outline, folding, tokens), a run between two looks
    runs = 3 * -(-rungs // RUN)
    assert len(analysis.memo.runs) == runs and seen.count(done) >= runs


def test_the_warm_up_makes_ready_the_drawings_an_unreadable_element_is_compared_with():
    """The first edit that leaves an element unreadable (typing can, for a
    moment) would wait for them: the examples read and drawn, 30 ms."""
    import asyncio

    from lang import reference
    from lsp import warmup

    _, server = opened_document(20)
    reference._known.cache_clear()
    asyncio.run(warmup.warm(server, "file:///w.ladder"))
    assert reference._known.cache_info().currsize == 1


def test_the_warm_up_waits_while_an_answer_is_being_written():
    """The diagnostics of an open are written by the writer thread while the
    warm-up begins; its slices, each after a zero-timeout poll, kept that thread
    from the interpreter's lock until the warm-up was done (about one open of
    four: 330 ms rather than 160 at the wire). The warm-up does nothing while
    the writer has an answer to write, and goes on once it is written."""
    import asyncio
    import os
    import threading

    from lsp import warmup
    from lsp.transport import PIPE_BYTES, PipeWriter

    read_end, write_end = os.pipe()
    writer = PipeWriter(os.fdopen(write_end, "wb"))
    answer = b"x" * (2 * PIPE_BYTES)  # more than the pipe holds: written only as the client reads
    writer.write(answer)
    analysis, server = opened_document(40, writer)
    received = bytearray()
    reads = threading.Event()  # the client starts reading

    def client() -> None:
        reads.wait()
        with os.fdopen(read_end, "rb") as pipe:
            while len(received) < len(answer):
                received.extend(pipe.read1(1 << 16))

    async def run() -> None:
        task = asyncio.ensure_future(warmup.warm(server, "file:///w.ladder"))
        await asyncio.sleep(0.1)
        assert analysis.memo.values == {} and writer.busy  # nothing worked out while the answer waits
        reads.set()
        await asyncio.wait_for(task, 30)

    reading = threading.Thread(target=client)
    reading.start()
    try:
        asyncio.run(run())
    finally:
        reads.set()
        writer.close()
        reading.join()
    assert bytes(received) == answer and len(analysis.memo.values) == 4 * 40
