"""An element drawn as one read before but for its names. A converted
program repeats a few rungs with other names (`Cnew10:0` over `[CTU>=4]`,
then `Cnew11:0`): the texts of their elements differ in names alone, so the
cache of element readings by text (lang/textform/rungs.py `_element_plan`)
misses every copy. Such an element reads as the known one with the new
names, which is shown here without reading it again:

* the two texts on top are the same but for words where the known one's
  names stand: the places of operands read as written (no format, no flag),
  each a whole word of letters, digits and `_`; each new name stands once
  in the new text;
* the instruction's drawing is the first of the glyph's that reads text on
  top, so `recognise` tries no other one before it; its pattern matches the
  new text with the same groups but for the renamed operands (so every
  other operand reads the same);
* no other operand value the reader looks for contains an old or a new
  name: its whole-word places in the text are then those it had.

Then the instruction, the operands (the renamed ones new) and every place
are the known element's."""

from __future__ import annotations

import re
from dataclasses import dataclass

from .elements import named_reader

# an element's reading: instruction, all its operands, and where each drawn operand stands
# (name, in the text on top, column from the start of that text or of the glyph, width)
ElementPlan = tuple[str, dict[str, object], tuple[tuple[str, bool, int, int], ...]]

_WORD_CHARS = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_"
# the mask of a text's UTF-8 bytes (surrogates passed, so any text encodes, and one way only):
# twice as quick as a str.translate, and the same mask, as only ASCII characters are masked
_MASK = bytes.maketrans(_WORD_CHARS.encode(), b"w" * len(_WORD_CHARS))
_WORDS = re.compile(r"[A-Za-z0-9_]+")
_MAX_KNOWN = 16384  # bounded as the recipes are, the oldest out first


@dataclass(frozen=True, slots=True)
class _Known:
    top: str
    plan: ElementPlan
    reader: re.Pattern  # the pattern of the text on top
    groups: dict[str, str | None]  # its groups in the known text
    names: tuple[tuple[int, int, str], ...]  # (start, end, operand) of each name a copy may rename, left to right
    searched: tuple[tuple[str, str], ...]  # (operand, value) of every drawn value the reader placed or looked for


_KNOWN: dict[tuple, _Known] = {}


def _key(glyph: str, top: str, glyph_edges: tuple[str, str], top_edges: tuple[str, str]) -> tuple:
    return glyph, glyph_edges, top_edges, top.encode("utf-8", "surrogatepass").translate(_MASK)


def remember(glyph: str, top: str, glyph_edges: tuple[str, str], top_edges: tuple[str, str],
             plan: ElementPlan, searched: tuple[tuple[str, str], ...]) -> None:
    """Keep an element read in full, when it has a name on top a copy may rename."""
    key, _, places = plan
    found = named_reader(glyph, key) if top.strip() else None
    if found is None:
        return
    reader, plain = found
    names = sorted((col, col + width, name) for name, on_top, col, width in places
                   if on_top and name in plain and _WORDS.fullmatch(top, col, col + width))
    match = reader.match(top)
    if not names or match is None:
        return
    if len(_KNOWN) >= _MAX_KNOWN:
        _KNOWN.pop(next(iter(_KNOWN)), None)
    _KNOWN.setdefault(_key(glyph, top, glyph_edges, top_edges),
                      _Known(top, plan, reader, match.groupdict(), tuple(names), searched))


def renamed(glyph: str, top: str, glyph_edges: tuple[str, str], top_edges: tuple[str, str]) -> ElementPlan | None:
    """The reading of an element whose text on top renames a known one's
    names (above), or None."""
    known = _KNOWN.get(_key(glyph, top, glyph_edges, top_edges))
    if known is None:
        return None
    old = known.top
    renames: dict[str, tuple[str, str]] = {}
    at = 0
    for start, end, name in known.names:
        if start < at or top[at:start] != old[at:start]:
            return None
        word, new = old[start:end], top[start:end]
        if word != new:
            if top.count(new) != 1:
                return None
            renames[name] = (word, new)
        at = end
    if top[at:] != old[at:]:
        return None
    match = known.reader.match(top)
    if match is None:
        return None
    groups = match.groupdict()
    for name, (word, new) in renames.items():
        if groups[name] != new:
            return None
        groups[name] = word
    if groups != known.groups:
        return None
    for name, value in known.searched:
        if name not in renames:
            for word, new in renames.values():
                if word in value or new in value:
                    return None
    key, args, places = known.plan
    args = dict(args)
    for name, (_, new) in renames.items():
        args[name] = new
    return key, args, places
