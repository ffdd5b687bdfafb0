"""The formatter: the canonical text of a program, keeping what keeps diffs
small (the diagram width the file already has, its line endings)."""

from __future__ import annotations

from ..diagnostics import ERROR, Diagnostic
from ..drawing import CELL
from .reader import RAIL_RE, read_text
from .writer import render_program


def existing_width(text: str) -> int | None:
    """The diagram width in cells, as the file's END rung shows it."""
    for line in text.splitlines():
        if "[END]" in line:
            rail = RAIL_RE.search(line)
            if rail is None:
                return None
            drawn = line.rstrip()
            end = len(drawn) - 2 if drawn.endswith("||") else len(drawn)
            return max(1, (end - rail.end()) // CELL)
    return None


def newline_of(text: str) -> str:
    return "\r\n" if "\r\n" in text else "\n"


def format_text(text: str, reflow: bool = False) -> tuple[str | None, list[Diagnostic]]:
    """The formatted text, or None when the file has errors (a file that
    cannot be read is never rewritten: no text may be lost)."""
    program, problems = read_text(text)
    if any(p.severity == ERROR for p in problems):
        return None, problems
    width = None if reflow else existing_width(text)
    formatted = render_program(program, width)
    newline = newline_of(text)
    if newline != "\n":
        formatted = formatted.replace("\n", newline)
    return formatted, problems
