"""Semantic tokens: instructions, names coloured by their role (inputs,
outputs, relays, timers and counters, variables), constants, labels,
comments, rung numbers and section titles, in the model's positions (0-based
lines, character columns). Positions come from the model's spans (ide.locate
for the glyphs). The language server maps the types to its legend."""

from __future__ import annotations

import re
from enum import IntEnum
from typing import NamedTuple

from lang.loader import LD_KIND, TEXT_KIND
from lang.model import Span
from lang.values import format_delay, is_literal

from .document import Document


class TokenType(IntEnum):
    """In the order of the server's legend: tokens at one place sort by it."""

    KEYWORD = 0  # an instruction's glyph, a .ld keyword
    PARAMETER = 1  # an input name: X, I, A
    PROPERTY = 2  # an output name: Y, M, P
    VARIABLE = 3  # a relay, a general variable
    FUNCTION = 4  # a timer, a counter
    NUMBER = 5
    STRING = 6
    LABEL = 7
    COMMENT = 8
    NAMESPACE = 9  # a section title
    MACRO = 10  # a `#` hardware register
    ENUM_MEMBER = 11


class Token(NamedTuple):
    """A named tuple, as `Span`: a big program has tens of thousands, sorted
    by place."""

    line: int
    col: int
    length: int
    type: TokenType
    writes: bool  # the element writes that name there


# first letter -> token type: inputs are parameters, outputs properties, relays
# and plain variables variables, timers and counters functions
ROLE_TYPE = {"X": TokenType.PARAMETER, "I": TokenType.PARAMETER, "A": TokenType.PARAMETER,
             "Y": TokenType.PROPERTY, "M": TokenType.PROPERTY, "P": TokenType.PROPERTY,
             "R": TokenType.VARIABLE, "T": TokenType.FUNCTION, "C": TokenType.FUNCTION, "#": TokenType.MACRO}
_LD_KEYWORD = re.compile(r"\s*([A-Z0-9_]+)")


def role_type(name: str) -> TokenType:
    return ROLE_TYPE.get(name[:1], TokenType.VARIABLE)


def rung_tokens(document: Document, index: int) -> list[Token]:
    """The tokens of one rung, sorted, not overlapping."""
    found: list[Token] = []

    def add(span: Span | None, kind: TokenType, writes: bool = False) -> None:
        if span is None or span.line != span.end_line or span.end_col <= span.col:
            return
        found.append(Token(span.line, span.col, span.end_col - span.col, kind, writes))

    locator = document.locator
    rung = document.program.rungs[index]
    for element in rung.elements():
        if element.kind == "COMMENT":
            span = element.span
            if span is not None:
                for number in range(span.line, span.end_line + 1):
                    text = document.line(number)
                    start = text.find(";")
                    if start >= 0:
                        end = len(text.rstrip().rstrip("|").rstrip())
                        add(Span.at(number, start, max(end, start + 1)), TokenType.COMMENT)
            continue
        operand_spans = []
        for f in element.spec.fields:
            arg_span = element.arg_spans.get(f.name)
            value = element.args.get(f.name)
            if arg_span is None or not isinstance(value, (str, int)):
                continue
            operand_spans.append(arg_span)
            if f.kind == "label":
                add(arg_span, TokenType.LABEL)
            elif f.kind == "text":
                add(arg_span, TokenType.STRING)
            elif f.kind in ("bit", "var", "operand", "delay") and isinstance(value, str) \
                    and value and not is_literal(value):
                add(arg_span, role_type(value), f.access in ("write", "rw"))
            elif f.kind in ("operand", "delay", "int") or isinstance(value, int):
                add(arg_span, TokenType.NUMBER)
        if document.kind == LD_KIND:
            if element.span is not None:
                match = _LD_KEYWORD.match(document.line(element.span.line))
                if match:
                    add(Span.at(element.span.line, match.start(1), match.end(1)), TokenType.KEYWORD)
            continue
        glyph = locator.glyph_span(element)
        # values the reader parsed to numbers carry no span: find their text in the glyph
        for f in element.spec.fields:
            value = element.args.get(f.name)
            if f.drawn and f.name not in element.arg_spans and f.kind == "delay" and isinstance(value, int):
                shown = format_delay(value)
                at = document.line(glyph.line).find(shown, glyph.col, glyph.end_col)
                if at >= 0:
                    delay_span = Span.at(glyph.line, at, at + len(shown))
                    operand_spans.append(delay_span)
                    add(delay_span, TokenType.NUMBER)
        # the glyph, less the operands drawn inside it
        pieces = [(glyph.col, glyph.end_col)]
        for operand in operand_spans:
            if operand.line != glyph.line:
                continue
            next_pieces = []
            for a, b in pieces:
                if operand.end_col <= a or operand.col >= b:
                    next_pieces.append((a, b))
                    continue
                if a < operand.col:
                    next_pieces.append((a, operand.col))
                if operand.end_col < b:
                    next_pieces.append((operand.end_col, b))
            pieces = next_pieces
        for a, b in pieces:
            piece = document.line(glyph.line)[a:b]
            stripped = piece.strip()
            if stripped:
                offset = piece.index(stripped[0])
                add(Span.at(glyph.line, a + offset, a + offset + len(stripped)), TokenType.KEYWORD)
    extent = locator.rung_lines(index)
    if extent is not None:
        first, last = extent
        if document.kind == TEXT_KIND:
            for number in range(first, last + 1):
                label = document.line(number)[:4]
                if label.strip().isdigit():
                    start = len(label) - len(label.lstrip())
                    add(Span.at(number, start, len(label.rstrip())), TokenType.NUMBER)
        elif document.kind == LD_KIND:
            text = document.line(first)
            if text.strip().startswith("RUNG"):
                start = text.index("RUNG")
                add(Span.at(first, start, start + 4), TokenType.KEYWORD)
    return clean(found)


def clean(found: list[Token]) -> list[Token]:
    """Sorted, without overlaps: the first token at a place wins."""
    found.sort()
    result: list[Token] = []
    end = (-1, -1)
    for token in found:
        if (token.line, token.col) < end:
            continue
        result.append(token)
        end = (token.line, token.col + token.length)
    return result


def other_tokens(document: Document, first_line: int, last_line: int) -> list[Token]:
    """The tokens outside the rungs, between two lines: section titles, the
    part, the pin list; sorted, not overlapping."""
    extra: list[Token] = []

    def add(span: Span | None, kind: TokenType) -> None:
        if span is not None and span.line == span.end_line and span.end_col > span.col \
                and first_line <= span.line <= last_line:
            extra.append(Token(span.line, span.col, span.end_col - span.col, kind, False))

    if document.kind == TEXT_KIND:
        for title, first, _ in document.locator.sections:
            if title != "header":
                add(Span.at(first, 0, len(document.line(first).rstrip())), TokenType.NAMESPACE)
        add(document.program.settings.mcu_span, TokenType.STRING)
        for name, assignment in document.program.pins.items():
            add(assignment.span, role_type(name))
    return clean(extra)
