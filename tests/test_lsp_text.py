"""lsp/text.py: a document kept as lines gives pygls's text after any
incremental change, and says truly which lines no change touched."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from lsprotocol import types
from pygls.workspace import TextDocument
from pygls.workspace.position_codec import PositionCodec

from lsp.text import LineDocument

PIECES = st.sampled_from(["a", "é", "😋", "||--] [--", " ", "\n", "\r\n", "\r", "\n\n", "\x0c", "\u2028"])
TEXTS = st.lists(PIECES, max_size=30).map("".join)


@st.composite
def changes(draw):
    start = types.Position(line=draw(st.integers(0, 8)), character=draw(st.integers(0, 12)))
    end_line = draw(st.integers(start.line, start.line + 3))
    end_char = draw(st.integers(start.character if end_line == start.line else 0, 14))
    return types.TextDocumentContentChangePartial(
        range=types.Range(start=start, end=types.Position(line=end_line, character=end_char)), text=draw(TEXTS))


@settings(max_examples=400, deadline=None)
@given(TEXTS, st.lists(changes(), min_size=1, max_size=6), st.sampled_from(["utf-16", "utf-8", "utf-32"]))
def test_the_lines_are_pygls_text_after_any_changes(text, edits, encoding):
    codec = PositionCodec(encoding=encoding)
    ours = LineDocument("file:///t.ladder", text, position_codec=codec)
    theirs = TextDocument("file:///t.ladder", text, position_codec=codec)
    ours.take_edited()
    before = list(ours.lines)
    for change in edits:
        ours.apply_change(change)
        theirs.apply_change(change.__class__(range=change.range, text=change.text))
        assert ours.source == theirs.source
        assert list(ours.lines) == list(theirs.lines)
    edited = ours.take_edited()
    start, tail, after = edited.start, edited.tail, list(edited.lines)
    assert start + tail <= min(len(before), len(after))
    assert before[:start] == after[:start]
    assert before[len(before) - tail:] == after[len(after) - tail:]


def test_a_first_look_and_a_whole_text_change_say_nothing_is_known():
    document = LineDocument("file:///t.ladder", "a\nb\n")
    assert document.take_edited() is None
    document.apply_change(types.TextDocumentContentChangeWholeDocument(text="c\n"))
    assert document.take_edited() is None
    edited = document.take_edited()
    assert (edited.start, edited.tail, list(edited.lines)) == (1, 0, ["c\n"])
