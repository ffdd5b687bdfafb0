"""Semantic tokens: instructions, names coloured by their role (inputs,
outputs, relays, timers and counters, variables), constants, labels,
comments, rung numbers and section titles. Positions come from the model's
spans (ide.locate for the glyphs)."""

from __future__ import annotations

import re

from lsprotocol import types

from lang.model import Span
from lang.values import format_delay, is_literal

from .documents import LADDER, LD
from .protocol import Encoded

TOKEN_TYPES = ["keyword", "parameter", "property", "variable", "function", "number", "string", "label",
               "comment", "namespace", "macro", "enumMember"]
TOKEN_MODIFIERS = ["declaration", "modification", "readonly"]
LEGEND = types.SemanticTokensLegend(token_types=TOKEN_TYPES, token_modifiers=TOKEN_MODIFIERS)
_TYPE = {name: index for index, name in enumerate(TOKEN_TYPES)}
MODIFICATION = 1 << TOKEN_MODIFIERS.index("modification")

# first letter -> token type: inputs are parameters, outputs properties, relays
# and plain variables variables, timers and counters functions
ROLE_TYPE = {"X": "parameter", "I": "parameter", "A": "parameter", "Y": "property", "M": "property",
             "P": "property", "R": "variable", "T": "function", "C": "function", "#": "macro"}
_LD_KEYWORD = re.compile(r"\s*([A-Z0-9_]+)")


def _role(value: str) -> str:
    return ROLE_TYPE.get(value[:1], "variable")


def _rung_tokens(analysis, index: int) -> list[tuple[int, int, int, int, int]]:
    """The tokens of one rung, in code point columns, sorted."""
    found: list[tuple[int, int, int, int, int]] = []

    def add(span: Span | None, kind: str, modifiers: int = 0) -> None:
        if span is None or span.line != span.end_line or span.end_col <= span.col:
            return
        found.append((span.line, span.col, span.end_col - span.col, _TYPE[kind], modifiers))

    locator = analysis.locator
    rung = analysis.program.rungs[index]
    for element in rung.elements():
        if element.kind == "COMMENT":
            span = element.span
            if span is not None:
                for number in range(span.line, span.end_line + 1):
                    text = analysis.line(number)
                    start = text.find(";")
                    if start >= 0:
                        end = len(text.rstrip().rstrip("|").rstrip())
                        add(Span.at(number, start, max(end, start + 1)), "comment")
            continue
        operand_spans = []
        for f in element.spec.fields:
            span = element.arg_spans.get(f.name)
            value = element.args.get(f.name)
            if span is None or not isinstance(value, (str, int)):
                continue
            operand_spans.append(span)
            if f.kind == "label":
                add(span, "label")
            elif f.kind == "text":
                add(span, "string")
            elif f.kind in ("bit", "var", "operand", "delay") and isinstance(value, str) \
                    and value and not is_literal(value):
                add(span, _role(value), MODIFICATION if f.access in ("write", "rw") else 0)
            elif f.kind in ("operand", "delay", "int") or isinstance(value, int):
                add(span, "number")
        if analysis.kind == LD:
            text = analysis.line(element.span.line) if element.span else ""
            match = _LD_KEYWORD.match(text)
            if match:
                add(Span.at(element.span.line, match.start(1), match.end(1)), "keyword")
            continue
        glyph = locator.glyph_span(element)
        # values the reader parsed to numbers carry no span: find their text in the glyph
        for f in element.spec.fields:
            value = element.args.get(f.name)
            if f.drawn and f.name not in element.arg_spans and f.kind == "delay" and isinstance(value, int):
                shown = format_delay(value)
                at = analysis.line(glyph.line).find(shown, glyph.col, glyph.end_col)
                if at >= 0:
                    span = Span.at(glyph.line, at, at + len(shown))
                    operand_spans.append(span)
                    add(span, "number")
        # the glyph, less the operands drawn inside it
        pieces = [(glyph.col, glyph.end_col)]
        for span in operand_spans:
            if span.line != glyph.line:
                continue
            next_pieces = []
            for a, b in pieces:
                if span.end_col <= a or span.col >= b:
                    next_pieces.append((a, b))
                    continue
                if a < span.col:
                    next_pieces.append((a, span.col))
                if span.end_col < b:
                    next_pieces.append((span.end_col, b))
            pieces = next_pieces
        for a, b in pieces:
            piece = analysis.line(glyph.line)[a:b]
            stripped = piece.strip()
            if stripped:
                offset = piece.index(stripped[0])
                add(Span.at(glyph.line, a + offset, a + offset + len(stripped)), "keyword")
    extent = locator.rung_lines(index)
    if extent is not None:
        first, last = extent
        if analysis.kind == LADDER:
            for number in range(first, last + 1):
                label = analysis.line(number)[:4]
                if label.strip().isdigit():
                    start = len(label) - len(label.lstrip())
                    add(Span.at(number, start, len(label.rstrip())), "number")
        elif analysis.kind == LD:
            text = analysis.line(first)
            if text.strip().startswith("RUNG"):
                start = text.index("RUNG")
                add(Span.at(first, start, start + 4), "keyword")
    return _clean(found)


def _clean(found):
    found.sort()
    result, end = [], (-1, -1)
    for token in found:  # drop overlaps: the first token wins
        if (token[0], token[1]) < end:
            continue
        result.append(token)
        end = (token[0], token[1] + token[2])
    return result


def _extra(analysis, first_line: int, last_line: int) -> list[tuple[int, int, int, int, int]]:
    """The tokens outside the rungs: section titles, the part, the pin list."""
    extra: list[tuple[int, int, int, int, int]] = []

    def add(span: Span | None, kind: str) -> None:
        if span is not None and span.line == span.end_line and span.end_col > span.col \
                and first_line <= span.line <= last_line:
            extra.append((span.line, span.col, span.end_col - span.col, _TYPE[kind], 0))

    if analysis.kind == LADDER:
        for title, first, _ in analysis.locator.sections:
            if title != "header":
                add(Span.at(first, 0, len(analysis.line(first).rstrip())), "namespace")
        add(getattr(analysis.program.settings, "mcu_span", None), "string")
        for name, assignment in analysis.program.pins.items():
            add(assignment.span, _role(name))
    return extra


def tokens(analysis, first_line: int = 0, last_line: int | None = None) -> list[tuple[int, int, int, int, int]]:
    """(line, col, length, type, modifiers) in code point columns, sorted, not overlapping."""
    last_line = len(analysis.lines) - 1 if last_line is None else last_line
    found = _extra(analysis, first_line, last_line)
    for first, last, index in analysis.locator.rung_extents():
        if last < first_line or first > last_line:
            continue
        rung_tokens = analysis.per_rung("semantic", index, lambda i: _rung_tokens(analysis, i))
        if first_line <= first and last <= last_line:
            found.extend(rung_tokens)
        else:
            found.extend(t for t in rung_tokens if first_line <= t[0] <= last_line)
    return _clean(found)


def _client(analysis, found) -> list[tuple[int, int, int, int, int]]:
    """The tokens with their columns in the client's units."""
    positions, lines = analysis.positions, analysis.lines
    if positions.ascii:
        return found
    converted = []
    for line, col, length, kind, modifiers in found:
        if lines[line].isascii():
            converted.append((line, col, length, kind, modifiers))
        else:
            start = positions.to_client(line, col).character
            converted.append((line, start, positions.to_client(line, col + length).character - start, kind, modifiers))
    return converted


def encode(found, previous: tuple[int, int] = (0, 0)) -> list[int]:
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


def encoded_rung(analysis, index: int) -> tuple[int, int, int, int, str] | None:
    """A rung's tokens encoded, kept while the rung is unchanged."""
    return analysis.per_rung("semantic-encoded", index, lambda i: _encoded_rung(analysis, i))


def _encoded_rung(analysis, index: int) -> tuple[int, int, int, int, str] | None:
    """A rung's tokens kept encoded: (first line, first column, last line, last
    column, the JSON numbers of its tokens after the first's line and column)."""
    found = _client(analysis, _clean(list(analysis.per_rung("semantic", index, lambda i: _rung_tokens(analysis, i)))))
    if not found:
        return None
    first, last = found[0], found[-1]
    rest = encode(found, (first[0], first[1]))[2:]  # the first's deltas depend on what comes before
    return first[0], first[1], last[0], last[1], ",".join(map(str, rest))


def full_text(analysis) -> str:
    """The whole document's tokens as the JSON of SemanticTokens, from each
    rung's encoded part (an edit encodes only the rungs it changed)."""
    extra = _client(analysis, _clean(_extra(analysis, 0, len(analysis.lines) - 1)))
    parts: list[str] = []
    previous = (0, 0)
    position = 0

    def emit(tokens) -> None:
        nonlocal previous
        if tokens:
            parts.append(",".join(map(str, encode(tokens, previous))))
            previous = (tokens[-1][0], tokens[-1][1])

    for _, _, index in analysis.locator.rung_extents():
        part = encoded_rung(analysis, index)
        if part is None:
            continue
        first_line, first_col, last_line, last_col, rest = part
        before = position
        while position < len(extra) and extra[position][0] < first_line:
            position += 1
        emit(extra[before:position])
        delta_line = first_line - previous[0]
        head = f"{delta_line},{first_col - previous[1] if delta_line == 0 else first_col}"
        parts.append(f"{head},{rest}" if rest else head)
        previous = (last_line, last_col)
    emit(extra[position:])
    return '{"data":[' + ",".join(parts) + "]}"


def _shift(found, delta: int):
    return [(t[0] + delta,) + t[1:] for t in found]


def _shift_encoded(part, delta: int):
    if part is None:
        return None
    first_line, first_col, last_line, last_col, rest = part
    return first_line + delta, first_col, last_line + delta, last_col, rest


def register(server) -> None:
    server.documents.shifters["semantic"] = _shift
    server.documents.shifters["semantic-encoded"] = _shift_encoded
    @server.on(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
               types.SemanticTokensRegistrationOptions(legend=LEGEND, full=True, range=True))
    def full(ls, params: types.SemanticTokensParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        return Encoded(analysis.once("semantic", lambda: full_text(analysis)))

    @server.on(types.TEXT_DOCUMENT_SEMANTIC_TOKENS_RANGE)
    def ranged(ls, params: types.SemanticTokensRangeParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        first = params.range.start.line
        last = params.range.end.line
        return types.SemanticTokens(data=encode(_client(analysis, tokens(analysis, first, last))))
