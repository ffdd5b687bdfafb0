"""The adaptive diagnostics delay is measured on what checking a change
costs, not on an open (which reads and checks the whole document: hundreds of
ms for 2,000 rungs, while the edits after it are checked incrementally)."""

from __future__ import annotations

import time
from types import SimpleNamespace

from lsp.diagnostics import Publisher
from lsp.idle import IdleCollector
from lsp.settings import ADAPTIVE_DELAY_MS, QUICK_CHECK_MS, Settings


class SlowDocuments:
    def analysis(self, uri, include_too_large=False):
        time.sleep(QUICK_CHECK_MS / 1000 * 1.5)  # slower than a quick check
        return SimpleNamespace(diagnostics=[], positions=SimpleNamespace(ascii=True), version=1)


def test_an_open_does_not_set_the_delay_and_a_slow_change_does():
    sent = []
    server = SimpleNamespace(documents=SlowDocuments(), settings=Settings(), notify=lambda *args: sent.append(args))
    publisher = Publisher(server)
    publisher.publish("file:///a.ladder")  # an open
    assert sent and server.settings.delay_ms(publisher.last_duration_ms) == 0
    publisher.publish("file:///a.ladder", after_change=True)
    assert server.settings.delay_ms(publisher.last_duration_ms) == ADAPTIVE_DELAY_MS


def test_edits_read_one_after_the_other_are_published_once():
    """With the delay at 0, a publication waits for the input that has
    arrived to be read: of five edits queued while the server was busy, the
    last one is checked and published, once."""
    import asyncio

    class Documents:
        analyses = 0

        def analysis(self, uri, include_too_large=False):
            Documents.analyses += 1
            return SimpleNamespace(diagnostics=[], positions=SimpleNamespace(ascii=True), version=5)

    sent = []
    server = SimpleNamespace(documents=Documents(), settings=Settings(), notify=lambda *args: sent.append(args),
                             idle=IdleCollector())
    publisher = Publisher(server)

    async def burst():
        for _ in range(5):  # what the reader does with five didChange already in the pipe
            publisher.schedule("file:///a.ladder")
        assert not sent
        await asyncio.sleep(0)

    asyncio.run(burst())
    assert len(sent) == 1 and Documents.analyses == 1
