"""How one element is drawn in LDmicro's text export, and how to read it back.

An instruction's drawing is two layouts: the top (name) line and the symbol
line. Layouts are built from templates such as ``[TON {delay:delay}]`` or
``{set1?^|-}]{negated?/| }[-``; the same template renders the exact LDmicro
text and compiles into the regular expression that reads it back leniently
(any padding, any number of wire dashes).

LDmicro's three placement rules (ldmicro-formats.md §1.4) are kept, except
that nothing is ever truncated: where LDmicro would cut a name with ``~``, the
text is kept whole and the cell grows instead.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

from . import values

CELL = 17  # characters per grid cell (POS_WIDTH)

# --- value patterns -----------------------------------------------------------

NAME = r"(?:[^\W\d]|[$#@])[\w$#@.]*~?"
NUMBER = r"[-+]?\d[\w.]*~?"
CHAR = r"'(?:\\.|[^'\\])+'"
OPERAND = rf"(?:{CHAR}|{NUMBER}|{NAME})"
LABEL = r"[^\s\[\]{}()]+"
DELAY = rf"(?:{values.SI_NUMBER}\s*[GMkmunp]?s|{NAME})"

_KIND_PATTERNS = {
    "bit": NAME,
    "var": NAME,
    "name": NAME,
    "operand": OPERAND,
    "label": LABEL,
    "delay": DELAY,
    "edge": r"[/\\o]?",
    "int": NUMBER,
    "token": r"[^\s\[\]{}]+",
    "text": r".*?",
    "coil": r"[ /SRT]",
}


def _format_field(kind: str, fmt: str | None, value: object) -> str:
    kind = kind.rstrip("?")
    if fmt == "delay":
        return values.format_delay(value) if isinstance(value, int) else str(value)
    if fmt == "hz":
        return values.format_frequency(values.as_int(value))
    if fmt == "us":
        return f"{value} us" if values.is_literal(str(value)) else str(value)
    if fmt == "last":
        return str(values.as_int(value) - 1)
    if kind == "edge":
        return "-" if value in ("-", "", None) else str(value)
    return str(value)


def _parse_field(kind: str, fmt: str | None, text: str) -> object:
    kind = kind.rstrip("?")
    if fmt == "delay":
        try:
            return values.parse_delay(text)
        except ValueError:
            if re.fullmatch(NAME, text):
                return text
            raise
    if fmt == "hz":
        return values.parse_frequency(text)
    if fmt == "us":
        return text[:-2].strip() if text.endswith("us") else text
    if fmt == "last":
        return int(text) + 1
    if kind == "edge":
        return text or "-"
    if kind == "int":
        try:
            return int(text, 0)
        except ValueError:
            return text
    return text


# --- templates ------------------------------------------------------------------

_PLACEHOLDER = re.compile(r"\{\{|\}\}|\{(\w+)(?::(\w+))?(?:\?([^|}]*)\|([^}]*))?\}")


@cache
def _parts(text: str) -> tuple[tuple, ...]:
    found: list[tuple] = []
    pos = 0
    literal = ""
    for match in _PLACEHOLDER.finditer(text):
        literal += text[pos:match.start()]
        pos = match.end()
        if match.group(1) is None:  # an escaped brace
            literal += match.group(0)[0]
            continue
        if literal:
            found.append(("lit", literal))
            literal = ""
        found.append(("field", match.group(1), match.group(2), match.group(3), match.group(4)))
    literal += text[pos:]
    if literal:
        found.append(("lit", literal))
    return tuple(found)


@dataclass(frozen=True)
class Template:
    """Literal text with ``{field}``, ``{field:format}`` and ``{flag?yes|no}``."""

    text: str

    def parts(self) -> tuple[tuple, ...]:
        """("lit", text) and ("field", name, format, yes, no) in order (read
        once per template: every element read or drawn asks)."""
        return _parts(self.text)

    def fields(self) -> list[str]:
        return [part[1] for part in self.parts() if part[0] == "field"]

    def render(self, args: dict, kinds: dict[str, str]) -> str:
        out = []
        for part in self.parts():
            if part[0] == "lit":
                out.append(part[1])
                continue
            _, name, fmt, yes, no = part
            value = args[name]
            if yes is not None:
                out.append(yes if value else no)
            else:
                out.append(_format_field(kinds.get(name, "operand"), fmt, value))
        return "".join(out)

    def regex(self, kinds: dict[str, str], edges: bool = False, left: bool = True, right: bool = True) -> str:
        """A lenient pattern: literal blanks match any run of blanks; with
        ``edges`` the template's outer wire dashes (on the ``left`` and
        ``right`` ends) are optional."""
        parts = list(self.parts())
        pieces = []
        for index, part in enumerate(parts):
            if part[0] == "lit":
                text = part[1]
                if edges and left and index == 0:
                    text = text.lstrip("-")
                if edges and right and index == len(parts) - 1:
                    text = text.rstrip("-")
                pieces.append(_literal_regex(text))
                continue
            _, name, fmt, yes, no = part
            if yes is not None:
                options = [yes, no]
                optional = edges and "-" in options and ((left and index == 0) or (right and index == len(parts) - 1))
                alternatives = "|".join(re.escape(o) for o in options if o and not (optional and o == "-"))
                group = f"(?P<{name}>{alternatives})"
                pieces.append(group + ("?" if optional or "" in options else ""))
            else:
                kind = kinds.get(name, "operand")
                pattern = _KIND_PATTERNS.get(kind.rstrip("?"), OPERAND)
                if kind.endswith("?"):
                    pattern = f"(?:{pattern})?"
                if fmt == "hz":
                    pattern = rf"{values.SI_NUMBER}\s*[GMkmunp]?Hz"
                elif fmt == "us":
                    pattern = rf"(?:\d+\s*us|{NAME})"
                elif fmt == "last":
                    pattern = r"-?\d+"
                pieces.append(f"(?P<{name}>{pattern})")
        return "".join(pieces)


def _literal_regex(text: str) -> str:
    out = []
    for chunk in re.split(r"( +)", text):
        if not chunk:
            continue
        out.append(r"\s+" if chunk.startswith(" ") else re.escape(chunk))
    return "".join(out)


def read_fields(match: re.Match, templates: list[Template], kinds: dict[str, str]) -> dict:
    """Field values from a match of the templates' patterns."""
    found: dict[str, object] = {}
    for template in templates:
        for part in template.parts():
            if part[0] != "field":
                continue
            _, name, fmt, yes, no = part
            text = match.group(name)
            if yes is not None:
                found[name] = 1 if text == yes else 0
            else:
                found[name] = _parse_field(kinds.get(name, "operand"), fmt, text or "")
    return found


# --- layouts: where the text goes -----------------------------------------------

@dataclass(frozen=True)
class Text:
    """Text centred in the element's slot (LDmicro's P1 placement)."""

    template: Template

    def templates(self) -> list[Template]:
        return [self.template]

    def render(self, args: dict, kinds: dict[str, str], cells: int) -> str:
        return self.template.render(args, kinds)

    def regex(self, kinds: dict[str, str], edges: bool) -> str:
        # centred text carries no meaning in its outer blanks
        return Template(self.template.text.strip(" ")).regex(kinds, edges)


@dataclass(frozen=True)
class Box:
    """LDmicro's field formatter (P3): prefix, left, centre, right and suffix
    laid out in the element's width less one, free space split between the
    left/centre and centre/right gaps. ``width`` overrides the slot width
    (comparisons size their box to their operands)."""

    prefix: Template
    left: Template
    center: Template
    right: Template
    suffix: Template
    width: str | None = None  # name of a sizing rule in BOX_WIDTHS

    def templates(self) -> list[Template]:
        return [self.prefix, self.left, self.center, self.right, self.suffix]

    def render(self, args: dict, kinds: dict[str, str], cells: int) -> str:
        parts = [t.render(args, kinds) for t in self.templates()]
        total = BOX_WIDTHS[self.width](args) if self.width else CELL * cells
        budget = total - 1 if total >= CELL else total
        free = max(0, budget - sum(len(p) for p in parts))
        after_center = free // 2
        before_center = free - after_center
        gaps = [0, before_center, after_center, 0]
        # where LDmicro would cut a field, we grow instead; but two fields that
        # then touch must not run together into one token
        templates = self.templates()
        present = [i for i, part in enumerate(parts) if part]
        for a, b in zip(present, present[1:]):
            if (sum(gaps[a:b]) == 0 and templates[a].fields() and templates[b].fields()
                    and _wordish(parts[a][-1]) and _wordish(parts[b][0])):
                gaps[b - 1] = 1
        out = parts[0]
        for gap, part in zip(gaps, parts[1:]):
            out += " " * gap + part
        return out

    def regex(self, kinds: dict[str, str], edges: bool) -> str:
        pieces = [t.regex(kinds, edges and i in (0, 4), left=i == 0, right=i == 4)
                  for i, t in enumerate(self.templates())]
        return r"\s*".join(p for p in pieces if p)


def _wordish(ch: str) -> bool:
    return ch.isalnum() or ch in "_$#@.~'\"-+\\"


def _compare_width(args: dict) -> int:
    return min(CELL, max(len(str(args["op1"])) + len(str(args["op"])) + 3, len(str(args["op2"])) + 2))


BOX_WIDTHS = {"compare": _compare_width}


def T(text: str) -> Template:
    return Template(text)


def text(template: str) -> Text:
    return Text(Template(template))


def box(prefix: str, left: str, center: str, right: str, suffix: str, width: str | None = None) -> Box:
    return Box(T(prefix), T(left), T(center), T(right), T(suffix), width)


# --- LDmicro's placement primitives ---------------------------------------------

def center_offset(slot: int, length: int) -> int:
    """Column where a string starts when centred in a slot (C division)."""
    extra = slot - length
    return int(extra / 2)


def with_wires(glyph: str, slot: int) -> str:
    """P2: the glyph centred in the slot, dashes either side."""
    before = max(0, center_offset(slot, len(glyph)))
    after = max(0, slot - before - len(glyph))
    return "-" * before + glyph + "-" * after
