"""Recognising one drawn element: its glyph on the symbol line and the text
on the name line above it, matched against the instruction table's drawings.

Glyph tokens are found with one pattern for every shape the table draws
(brackets, braces, coils, contacts, SFR boxes, strings); which instruction a
token is then depends on both lines (`{MOV` and `{ADD` share a glyph shape).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cache, lru_cache

from ..drawing import read_fields
from ..instructions import INSTRUCTIONS, Instruction

# Shapes a glyph can take on a symbol line, strings first: their text may
# hold any character. The edge-kind prefixes (/ \ o ^) and the encoder's
# trailing ^ belong to the glyph.
GLYPH_RE = re.compile(
    r"""
      \{"(?:(?!"\}).)*?",[^{}]*\}      # STRING: {"format", var}
    | \{"(?:(?!"\}).)*"\}              # FORMATTED_STRING: {"text"}
    | [/\\o^]?\{(?:[^{}\[\]]|\[[^\[\]]*\])*\}      # braces, may hold one [index]
    | [/\\o^]?\[[^\[\]]*\]\^?          # brackets
    | \([^()]\)                        # coils
    | \^?\][ /]\[                      # contacts
    | \?[^?]*\?                        # SFR boxes
    """,
    re.X,
)


@dataclass(frozen=True)
class Candidate:
    instruction: Instruction
    glyph_re: re.Pattern
    top_re: re.Pattern | None
    head: str  # literal start of the glyph, for cheap dispatch
    kinds: dict[str, str] = field(compare=False)


def _head(pattern_text: str) -> str:
    """The literal characters a glyph must start with (after its optional
    edge prefix), taken from the rendered default glyph."""
    match = re.match(r"[-/\\o^]*([\[{(\]?][A-Za-z0-9 ]{0,4})", pattern_text)
    return match.group(1).rstrip() if match else ""


@cache
def _candidates() -> tuple[Candidate, ...]:
    found = []
    for instruction in INSTRUCTIONS.values():
        if instruction.glyph is None or instruction.key in ("SHORT", "OPEN", "PLACEHOLDER"):
            continue
        kinds = instruction.kinds
        glyph_re = re.compile(r"-*" + instruction.glyph.regex(kinds, edges=True) + r"-*\Z")
        top_re = None
        if instruction.top is not None:
            top_re = re.compile(r"\s*" + instruction.top.regex(kinds, edges=False) + r"\s*\Z")
        literal = "".join(
            part[1] for part in instruction.glyph.templates()[0].parts() if part[0] == "lit"
        )
        found.append(Candidate(instruction, glyph_re, top_re, _head(literal), kinds))
    return tuple(found)


@cache
def _by_head_char() -> dict[str, tuple[Candidate, ...]]:
    table: dict[str, list[Candidate]] = {}
    for candidate in _candidates():
        key = candidate.head[:1]
        table.setdefault(key, []).append(candidate)
    return {key: tuple(value) for key, value in table.items()}


def prepare() -> None:
    """Build the glyph tables now (the language server does when it starts,
    so that the first document it opens does not wait for them)."""
    _by_head_char()


def _shape_key(glyph: str) -> str:
    stripped = glyph.lstrip("/\\o^-")
    return stripped[:1]


@lru_cache(maxsize=4096)
def _glyph_reads(glyph: str) -> tuple[tuple[Candidate, tuple | str], ...]:
    """Each instruction a glyph can be, with the field values the glyph gives
    it (or why they are wrong): the same glyph stands under many names."""
    glyph_text = "-" + glyph + "-"
    found: list[tuple[Candidate, tuple | str]] = []
    for candidate in _by_head_char().get(_shape_key(glyph), ()):
        glyph_match = candidate.glyph_re.match(glyph_text)
        if not glyph_match:
            continue
        symbol = candidate.instruction.glyph
        assert symbol is not None  # _candidates() keeps the instructions that have one
        try:
            found.append((candidate, tuple(read_fields(glyph_match, symbol.templates(), candidate.kinds).items())))
        except ValueError as bad:
            found.append((candidate, str(bad)))
    return tuple(found)


@lru_cache(maxsize=65536)
def recognise(glyph: str, top: str) -> tuple[str, tuple] | None:
    """The instruction key and its drawn field values for a glyph and the
    text above it, or None if no instruction draws like that. Cached: real
    programs repeat the same elements many times."""
    for candidate, values in _glyph_reads(glyph):
        instruction = candidate.instruction
        if candidate.top_re is None:
            if top.strip():
                continue
            top_values: dict = {}
            if isinstance(values, str):
                raise ValueError(values)
        else:
            top_match = candidate.top_re.match(top)
            if not top_match:
                continue
            if isinstance(values, str):
                raise ValueError(values)
            assert instruction.top is not None  # top_re was made from it
            top_values = read_fields(top_match, instruction.top.templates(), candidate.kinds)
        return instruction.key, (*values, *top_values.items()) if top_values else values
    return None


def named_reader(glyph: str, key: str) -> tuple[re.Pattern, frozenset[str]] | None:
    """For an element of `key` drawn with this glyph and text on top: the
    pattern that reads that text and its fields that hold a name as written
    (no format, no flag), when `key`'s drawing is the first of the glyph's
    that reads text on top, so that `recognise` tries no other before it
    whatever the names; else None."""
    for candidate, _ in _glyph_reads(glyph):
        if candidate.top_re is None:
            continue  # skipped by `recognise` under text on top
        if candidate.instruction.key != key:
            return None
        return candidate.top_re, _plain_fields(key)
    return None


_PLAIN_KINDS = ("bit", "var", "name", "operand")  # read as written (lang.drawing._parse_field)


@cache
def _plain_fields(key: str) -> frozenset[str]:
    instruction = INSTRUCTIONS[key]
    top, kinds = instruction.top, instruction.kinds
    assert top is not None  # an instruction that reads text on top draws some
    return frozenset(part[1] for template in top.templates() for part in template.parts()
                     if part[0] == "field" and part[2] is None and part[3] is None
                     and kinds.get(part[1], "operand").rstrip("?") in _PLAIN_KINDS)


def complete_args(key: str, drawn: dict) -> dict:
    """All fields of the instruction in table order: drawn values, and the
    defaults of what the drawing does not show."""
    return {name: drawn.get(name, default) for name, default in _defaults(key)}


@cache
def _defaults(key: str) -> tuple[tuple[str, object], ...]:
    return tuple((f.name, f.default) for f in INSTRUCTIONS[key].fields)
