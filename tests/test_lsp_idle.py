"""The server's garbage collection policy (lsp/idle.py): while the client
is active nothing walks the whole heap; what is new is collected after a
second of quiet; the whole heap only after a long quiet, once a document
was closed or many edits were made."""

from __future__ import annotations

import pytest

from lsp import idle


class Clock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


@pytest.fixture
def collector(monkeypatch):
    calls = []
    monkeypatch.setattr(idle.gc, "collect", lambda *a: calls.append("collect") or 0)
    monkeypatch.setattr(idle.gc, "freeze", lambda: calls.append("freeze"))
    monkeypatch.setattr(idle.gc, "unfreeze", lambda: calls.append("unfreeze"))
    monkeypatch.setattr(idle.gc, "get_count", lambda: (0, 0, 0))
    clock = Clock()
    found = idle.IdleCollector(clock)
    found.calls = calls
    found.time = clock
    return found


def test_nothing_is_collected_while_the_client_is_active(collector):
    for _ in range(50):
        collector.touch()
        collector.time.now += 0.1
        collector.step()
    assert collector.calls == []


def test_after_a_second_of_quiet_only_what_is_new_is_collected(collector):
    collector.touch()
    collector.time.now += idle.QUIET_S
    collector.step()
    assert collector.calls == ["collect", "freeze"]  # no unfreeze: the frozen heap is not walked
    collector.time.now += idle.FULL_QUIET_S
    collector.step()
    assert collector.calls == ["collect", "freeze"]  # nothing new happened since


def test_a_long_burst_of_edits_freezes_what_is_new_without_walking_it(collector, monkeypatch):
    monkeypatch.setattr(idle.gc, "get_count", lambda: (0, 0, idle.MAX_DEFERRED + 1))
    collector.touch()
    collector.step()
    assert collector.calls == ["freeze"]
    assert collector.pauses == []  # no collection while the client is busy


def test_the_whole_heap_is_walked_after_a_close_and_a_long_quiet_only(collector):
    collector.touch()
    collector.released()
    collector.time.now += idle.QUIET_S
    collector.step()
    assert "unfreeze" not in collector.calls
    collector.time.now += idle.FULL_QUIET_S
    collector.step()
    assert collector.calls[-3:] == ["unfreeze", "collect", "freeze"]
    assert collector.pauses[-1][1:] == (True, True)
    collector.time.now += idle.FULL_QUIET_S
    collector.step()
    assert collector.calls.count("unfreeze") == 1


def test_many_edits_make_the_whole_heap_worth_walking(collector):
    for _ in range(idle.FULL_AFTER_EDITS):
        collector.touch()
    collector.time.now += idle.FULL_QUIET_S
    collector.step()
    assert collector.calls == ["unfreeze", "collect", "freeze"]
