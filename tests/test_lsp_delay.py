"""The adaptive diagnostics delay is measured on what checking a change
costs, not on an open (which reads and checks the whole document: hundreds of
ms for 2,000 rungs, while the edits after it are checked incrementally)."""

from __future__ import annotations

import time
from types import SimpleNamespace

from lsp.diagnostics import Publisher
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
