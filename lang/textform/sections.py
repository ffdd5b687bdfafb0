"""The blocks of a text file: header, LADDER DIAGRAM, I/O ASSIGNMENT, VAR LIST
and our own SETTINGS, DETAILS and PROPERTIES, located by shape as much as by title
(LDmicro translates some titles)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

HEADER_MAGIC = "LDmicro export text"
DIAGRAM = "LADDER DIAGRAM"
IO = "I/O ASSIGNMENT"
VARS = "VAR LIST"
SETTINGS = "SETTINGS"
DETAILS = "DETAILS"
PROPERTIES = "PROPERTIES"

_TITLE_RE = re.compile(r"([^\s|:][^|:]*):\s*\Z")


@dataclass
class Section:
    title: str  # one of the constants above, or the text of an unknown title
    title_line: int  # -1 for the header
    lines: list[tuple[int, str]] = field(default_factory=list)


def split_sections(lines: list[str]) -> list[Section]:
    """Sections in file order. The diagram runs from its title to the first
    line that is neither blank nor drawn between rails and is a title."""
    sections = [Section("header", -1)]
    current = sections[0]
    for number, text in enumerate(lines):
        # a title has no indent and no rail and ends in a colon: this test, inline, keeps the
        # hundreds of thousands of drawing lines of a big program from a call each
        if text[:1].isspace() or "|" in text or not text.rstrip().endswith(":"):
            current.lines.append((number, text))
            continue
        title = _title(text, lines, number, current)
        if title is not None:
            current = Section(title, number)
            sections.append(current)
            continue
        current.lines.append((number, text))
    return sections


def _title(text: str, lines: list[str], number: int, current: Section) -> str | None:
    match = _TITLE_RE.match(text)
    if not match:
        return None
    name = match.group(1).strip()
    upper = name.upper()
    for known in (DIAGRAM, VARS, SETTINGS, DETAILS, PROPERTIES):
        if upper == known:
            return known
    if upper == IO or _is_io_table(lines, number):
        return IO
    if current.title == "header" and not upper.startswith("FOR "):
        return None
    return name


def _is_io_table(lines: list[str], number: int) -> bool:
    """A translated I/O title is recognised by the table header under it."""
    following = lines[number + 1] if number + 1 < len(lines) else ""
    return following.count("|") >= 2
