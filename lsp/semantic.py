"""Semantic tokens (ide.tokens) in LSP's encoding: each token type by its
index in the legend, columns in the client's units, positions relative to
the token before. Each rung's tokens, and their encoding, are kept while the
rung is unchanged (`Analysis.per_rung`), the encodings joined in runs of
rungs (`Analysis.per_run`); after an edit a client that names the answer it
has gets the change from it (`semanticTokens/full/delta`)."""

from __future__ import annotations

import functools
import itertools
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

from lsprotocol import types

from ide.tokens import Token, TokenType, clean, other_tokens, rung_tokens

from .documents import Analysis
from .protocol import Encoded

if TYPE_CHECKING:
    from .server import LadderServer

LSP_TYPES = {TokenType.KEYWORD: "keyword", TokenType.PARAMETER: "parameter", TokenType.PROPERTY: "property",
             TokenType.VARIABLE: "variable", TokenType.FUNCTION: "function", TokenType.NUMBER: "number",
             TokenType.STRING: "string", TokenType.LABEL: "label", TokenType.COMMENT: "comment",
             TokenType.NAMESPACE: "namespace", TokenType.MACRO: "macro", TokenType.ENUM_MEMBER: "enumMember"}
TOKEN_TYPES = [LSP_TYPES[kind] for kind in sorted(TokenType)]
TOKEN_MODIFIERS = ["declaration", "modification", "readonly"]
LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=TOKEN_MODIFIERS)
_INDEX = {kind: TOKEN_TYPES.index(LSP_TYPES[kind]) for kind in TokenType}
MODIFICATION = 1 << TOKEN_MODIFIERS.index("modification")

# (line, start, length, type, modifiers): a token as LSP counts it
Encodable = tuple[int, int, int, int, int]
# a rung's tokens encoded: (first line, first column, last line, last column, the JSON numbers of
# its tokens after the first's line and column)
EncodedRung = tuple[int, int, int, int, str]


def _rung_tokens(analysis: Analysis, index: int) -> list[Token]:
    return analysis.per_rung("semantic", index, lambda i: rung_tokens(analysis, i))


def tokens(analysis: Analysis, first_line: int = 0, last_line: int | None = None) -> list[Token]:
    """The tokens between two lines, sorted, not overlapping."""
    last_line = len(analysis.lines) - 1 if last_line is None else last_line
    found = other_tokens(analysis, first_line, last_line)
    for first, last, index in analysis.locator.rung_extents():
        if last < first_line or first > last_line:
            continue
        rung = _rung_tokens(analysis, index)
        if first_line <= first and last <= last_line:
            found.extend(rung)
        else:
            found.extend(t for t in rung if first_line <= t.line <= last_line)
    return clean(found)


def _client(analysis: Analysis, found: list[Token]) -> list[Encodable]:
    """The tokens with their columns in the client's units, their types and modifiers as numbers."""
    positions, lines = analysis.positions, analysis.lines
    converted = []
    for line, col, length, kind, writes in found:
        modifiers = MODIFICATION if writes else 0
        if positions.ascii or lines[line].isascii():
            converted.append((line, col, length, _INDEX[kind], modifiers))
        else:
            start = positions.to_client(line, col).character
            converted.append((line, start, positions.to_client(line, col + length).character - start, _INDEX[kind],
                              modifiers))
    return converted


def encode(found: Sequence[Encodable], previous: tuple[int, int] = (0, 0)) -> list[int]:
    """LSP's relative encoding of tokens in the client's units, from the token
    at `previous` (line, column)."""
    data: list[int] = []
    append = data.extend
    previous_line, previous_col = previous
    for line, start, length, kind, modifiers in found:
        delta_line = line - previous_line
        append((delta_line, start - previous_col if delta_line == 0 else start, length, kind, modifiers))
        previous_line, previous_col = line, start
    return data


def encoded_rung(analysis: Analysis, index: int) -> EncodedRung | None:
    """A rung's tokens encoded, kept while the rung is unchanged."""
    return analysis.per_rung("semantic-encoded", index, lambda i: _encoded_rung(analysis, i))


def _encoded_rung(analysis: Analysis, index: int) -> EncodedRung | None:
    found = _client(analysis, _rung_tokens(analysis, index))
    if not found:
        return None
    first, last = found[0], found[-1]
    rest = encode(found, (first[0], first[1]))[2:]  # the first's deltas depend on what comes before
    return first[0], first[1], last[0], last[1], ",".join(map(str, rest))


def _encoded_run(analysis: Analysis, run: Sequence[int]) -> EncodedRung | None:
    """The encoded tokens of consecutive rungs, as one rung's."""
    parts = [part for part in map(functools.partial(encoded_rung, analysis), run) if part is not None]
    if not parts:
        return None
    texts = [parts[0][4]]
    for (_, _, last_line, last_col, _), (first_line, first_col, _, _, rest) in zip(parts, parts[1:]):
        delta_line = first_line - last_line
        texts.append(f"{delta_line},{first_col - last_col if delta_line == 0 else first_col},{rest}")
    return parts[0][0], parts[0][1], parts[-1][2], parts[-1][3], ",".join(texts)


def runs(analysis: Analysis) -> Iterator[EncodedRung | None]:
    """The encoded tokens of the runs of rungs, one run at a time."""
    indexes = [index for _, _, index in analysis.locator.rung_extents()]
    return analysis.per_run("semantic-run", indexes, lambda run: _encoded_run(analysis, run), _shift_encoded)


def full_text(analysis: Analysis) -> str:
    """The whole document's tokens as the JSON of SemanticTokens, from the
    encoded parts of runs of rungs (`Analysis.per_run`): an edit encodes only
    the rungs it changed and joins their runs again; a run a line added above
    moved is the same numbers, but for its first and last tokens' lines. The
    tokens outside the rungs (section titles, the part, the I/O table's pins)
    lie outside the diagram, never between two of its rungs."""
    extra = _client(analysis, other_tokens(analysis, 0, len(analysis.lines) - 1))
    parts: list[str] = []
    previous = (0, 0)
    position = 0

    def emit(found: list[Encodable]) -> None:
        nonlocal previous
        if found:
            parts.append(",".join(map(str, encode(found, previous))))
            previous = (found[-1][0], found[-1][1])

    for part in runs(analysis):
        if part is None:
            continue
        first_line, first_col, last_line, last_col, rest = part
        before = position
        while position < len(extra) and extra[position][0] < first_line:
            position += 1
        emit(extra[before:position])
        delta_line = first_line - previous[0]
        parts.append(f"{delta_line},{first_col - previous[1] if delta_line == 0 else first_col},{rest}")
        previous = (last_line, last_col)
    emit(extra[position:])
    return '{"data":[' + ",".join(parts) + "]}"

def _shift(found: list[Token], delta: int) -> list[Token]:
    return [Token(t.line + delta, t.col, t.length, t.type, t.writes) for t in found]


def _shift_encoded(part: EncodedRung | None, delta: int) -> EncodedRung | None:
    if part is None:
        return None
    first_line, first_col, last_line, last_col, rest = part
    return first_line + delta, first_col, last_line + delta, last_col, rest


# the numbers of two answers compared this many characters at a time
_CHUNK = 1 << 16


def _common_prefix(a: str, b: str) -> int:
    """The length of the longest common prefix (slices compared by C, a chunk at a time)."""
    at = 0
    limit = min(len(a), len(b))
    while at < limit and a[at:at + _CHUNK] == b[at:at + _CHUNK]:
        at += _CHUNK
    at = min(at, limit)
    end = min(at + _CHUNK, limit)
    while at < end and a[at] == b[at]:
        at += 1
    return at


def _numbers(text: str) -> int:
    return text.count(",") + 1 if text else 0


def delta_edit(before: str, after: str) -> tuple[int, int, str] | None:
    """The one edit that turns the numbers `before` into `after` (each the
    JSON text between the brackets of `data`): (index of the first number
    replaced, how many are, the JSON text of those put instead), or None when
    they are the same. An edit of one rung changes its tokens and the first
    token's after it: one stretch of a big answer."""
    if before == after:
        return None
    # the numbers both start with, whole: up to the last comma of their common start
    start = before.rfind(",", 0, _common_prefix(before, after)) + 1
    # and those both end with, from the first comma of their common end
    tail = min(_common_prefix(before[::-1], after[::-1]), len(before) - start, len(after) - start)
    comma = before.find(",", len(before) - tail)
    kept = len(before) - comma if tail and comma >= 0 else 0
    old, new = before[start:len(before) - kept], after[start:len(after) - kept]
    return before.count(",", 0, start), _numbers(old), new


def register(server: LadderServer) -> None:
    server.documents.shifters["semantic"] = _shift
    server.documents.shifters["semantic-encoded"] = _shift_encoded
    # uri -> the result id and the numbers of the last full answer or delta sent
    sent: dict[str, tuple[str, str]] = {}
    counter = itertools.count(1)

    def numbers(analysis: Analysis) -> str:
        return analysis.once("semantic", lambda: full_text(analysis))[len('{"data":['):-len("]}")]

    def remember(uri: str, data: str) -> str:
        """A new result id for the numbers sent."""
        result_id = str(next(counter))
        sent[uri] = (result_id, data)
        return result_id

    def answer(uri: str, data: str) -> Encoded:
        return Encoded(f'{{"resultId":"{remember(uri, data)}","data":[{data}]}}')

    @server.on(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
               types.SemanticTokensRegistrationOptions(legend=LEGEND, full=types.SemanticTokensFullDelta(delta=True),
                                                       range=True))
    def full(ls: LadderServer, params: types.SemanticTokensParams) -> Encoded | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        return answer(analysis.uri, numbers(analysis))

    @server.on(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL_DELTA)
    def delta(ls: LadderServer, params: types.SemanticTokensDeltaParams) -> Encoded | None:
        """The edit from the answer the client names to this version's: a
        few numbers where the whole answer of 18,000 rungs is 1.8 MB; the
        whole answer when the server no longer has the one named."""
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        data = numbers(analysis)
        result_id, before = sent.get(analysis.uri, ("", ""))
        if result_id != params.previous_result_id:
            return answer(analysis.uri, data)
        edit = delta_edit(before, data)
        edits = "" if edit is None else f'{{"start":{edit[0]},"deleteCount":{edit[1]},"data":[{edit[2]}]}}'
        return Encoded(f'{{"resultId":"{remember(analysis.uri, data)}","edits":[{edits}]}}')

    @server.on(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_RANGE)
    def ranged(ls: LadderServer, params: types.SemanticTokensRangeParams) -> types.SemanticTokens | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        first = params.range.start.line
        last = params.range.end.line
        return types.SemanticTokens(data=encode(_client(analysis, tokens(analysis, first, last))))

    def closed(ls: LadderServer, uri: str | None) -> None:
        sent.pop(uri or "", None)

    server.subscribe("closed", closed)
