"""The whole-document answers (document symbols, folding ranges, semantic
tokens) as the language server keeps them between versions, in process: an
edit of one rung of 18,000 works out that rung's parts alone, and after
random edits each answer is the one a server that has just opened the text
gives."""

from __future__ import annotations

import json
import random
from types import SimpleNamespace

import pytest
from builders import coil, contact, program
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pygls.workspace import Workspace
from test_lsp_incremental import EDIT_CHARS, big_text, change_of, edits

import ide.outline
import lsp.semantic
from lang.textform.writer import render_program
from lsp import semantic, symbols
from lsp.documents import Analysis, Documents
from lsp.settings import Settings
from lsp.text import LineWorkspace

URI = "file:///whole.ladder"


class Server:
    """What lsp.documents and the two feature modules need of a server."""

    def __init__(self, text: str):
        self.workspace = LineWorkspace.like(Workspace(None))
        self.settings = Settings()
        self.documents = Documents(self)  # type: ignore[arg-type]
        registrar = SimpleNamespace(documents=self.documents, on=lambda *args, **kwargs: (lambda fn: fn),
                                    subscribe=lambda *args: None)
        symbols.register(registrar)  # type: ignore[arg-type]
        semantic.register(registrar)  # type: ignore[arg-type]
        self.version = 1
        self.workspace.put_text_document(types.TextDocumentItem(uri=URI, language_id="ladder", version=1, text=text))

    def log(self, *args: object) -> None:
        pass

    def change(self, change: types.TextDocumentContentChangePartial) -> None:
        self.version += 1
        self.workspace.update_text_document(types.VersionedTextDocumentIdentifier(uri=URI, version=self.version),
                                            change)

    @property
    def lines(self) -> list[str]:
        return list(self.workspace.get_text_document(URI).lines)

    def analysis(self) -> Analysis:
        found = self.documents.analysis(URI)
        assert found is not None
        return found


def answers(server: Server) -> dict[str, object]:
    """The three answers, as the client reads them."""
    analysis = server.analysis()
    return {"symbols": json.loads(symbols.document_symbols(analysis)),
            "folding": json.loads(symbols.folding_ranges(analysis)),
            "tokens": json.loads(semantic.full_text(analysis))["data"]}


def same_as_fresh(server: Server) -> None:
    kept = answers(server)
    fresh = Server("".join(server.lines))
    assert kept == answers(fresh)
    # the semantic tokens of every line, as the range request encodes them without the kept parts
    analysis = fresh.analysis()
    assert kept["tokens"] == semantic.encode(semantic._client(analysis, semantic.tokens(analysis)))
    # a client without hierarchical symbols gets the same symbols, flat
    assert symbols.flat_symbols(server.analysis()) == symbols._flat(kept["symbols"], URI)


@pytest.mark.slow  # about 10 s: the first answers of 18,000 rungs
def test_an_edit_of_one_rung_of_18000_works_out_that_rung_alone(monkeypatch):
    rungs = [[contact(f"X{n}"), contact(f"R{n}", negated=1), coil(f"R{n + 1}")] for n in range(18_000)]
    server = Server(render_program(program(*rungs)))
    answers(server)
    counted = {"symbol": [], "fold": [], "tokens": []}

    def counting(key, function):
        def counted_call(document, index):
            counted[key].append(index)
            return function(document, index)
        return counted_call

    monkeypatch.setattr(ide.outline, "rung_symbol", counting("symbol", ide.outline.rung_symbol))
    monkeypatch.setattr(ide.outline, "rung_fold", counting("fold", ide.outline.rung_fold))
    monkeypatch.setattr(lsp.semantic, "rung_tokens", counting("tokens", lsp.semantic.rung_tokens))
    line = next(n for n, text in enumerate(server.lines) if "R9000 " in text)
    col = server.lines[line].index("R9000") + 1
    server.change(types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(line=line, character=col),
                          end=types.Position(line=line, character=col + 1)), text="Q"))
    after = answers(server)
    edited = server.analysis().locator.rung_at(line)
    assert counted == {"symbol": [edited], "fold": [edited], "tokens": [edited]}
    diagram = next(s for s in after["symbols"] if s["name"] == "LADDER DIAGRAM")
    assert "RQ000" in diagram["children"][edited]["detail"]


@settings(max_examples=15, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
          deadline=None)
@given(data=st.data())
def test_answers_kept_after_random_edits_are_those_of_a_fresh_open(data):
    text = big_text(160)
    server = Server(text)
    answers(server)
    for step in data.draw(edits(text)):
        server.change(change_of(server.workspace.get_text_document(URI), step))
        if data.draw(st.booleans()):
            answers(server)
    same_as_fresh(server)


def test_answers_kept_along_a_longer_session_are_those_of_a_fresh_open():
    """Many versions, each answered: runs of rungs kept, rebuilt, moved by lines added and removed."""
    rng = random.Random(5)
    server = Server(big_text(300))
    for _ in range(40):
        step = (rng.choice(["type", "delete", "line-dup", "line-del", "replace"]), rng.randrange(10**6),
                rng.randrange(10**6), rng.choice(EDIT_CHARS))
        server.change(change_of(server.workspace.get_text_document(URI), step))
        answers(server)
    same_as_fresh(server)



def applied(data: list[int], edit: tuple[int, int, str] | None) -> list[int]:
    if edit is None:
        return data
    start, deleted, put = edit
    return data[:start] + json.loads(f"[{put}]") + data[start + deleted:]


@given(before=st.lists(st.integers(0, 120), max_size=40), data=st.data())
def test_the_semantic_tokens_delta_turns_the_answer_before_into_this_one(before, data):
    after = list(before)
    for _ in range(data.draw(st.integers(0, 3))):
        at = data.draw(st.integers(0, len(after)))
        after[at:at + data.draw(st.integers(0, 6))] = data.draw(st.lists(st.integers(0, 120), max_size=6))
    edit = semantic.delta_edit(",".join(map(str, before)), ",".join(map(str, after)))
    assert applied(before, edit) == after
    assert (edit is None) == (before == after)


def test_the_semantic_tokens_delta_of_an_edit_of_one_rung_is_that_rung_and_the_next_token():
    text = big_text(160)
    server = Server(text)
    before = answers(server)["tokens"]
    line = next(n for n, text_line in enumerate(server.lines) if "Xstart" in text_line and n > len(server.lines) // 2)
    col = server.lines[line].index("Xstart") + 1
    server.change(types.TextDocumentContentChangePartial(
        range=types.Range(start=types.Position(line=line, character=col),
                          end=types.Position(line=line, character=col)), text="q"))
    after = answers(server)["tokens"]
    edit = semantic.delta_edit(",".join(map(str, before)), ",".join(map(str, after)))
    assert applied(before, edit) == after
    assert edit is not None and edit[1] <= 5 * 40 and len(json.loads(f"[{edit[2]}]")) <= 5 * 40
