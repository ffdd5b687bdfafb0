"""Reading a document again and again as it is edited (the language server):
`IncrementalReader(kind)` reads `.ld` text whole (`lang.loader.parse`) and the
text form through a `lang.textform.reader.TextReader`, which re-reads only
the rungs an edit touches; `format_read` formats a text already read.
"""

from __future__ import annotations

from lang.diagnostics import Diagnostic
from lang.loader import LD_KIND, parse
from lang.model import Program, Rung
from lang.textform.reader import Edited, TextReader


class IncrementalReader:
    def __init__(self, kind: str):
        self.kind = kind
        self._text = TextReader()

    @property
    def moved(self) -> dict[int, tuple[Rung, int]]:
        """Rungs of the last read that are rungs of the read before moved by
        lines added or removed above them: id(new rung) -> (old rung, lines moved)."""
        return self._text.moved if self.kind != LD_KIND else {}

    @property
    def last_mode(self) -> str:
        """How the last read went: "same", "after", "window", "full" or "ld" (tests, benchmarks)."""
        return self._text.last_mode if self.kind != LD_KIND else "ld"

    @property
    def last_window(self) -> tuple[int, int]:
        return self._text.last_window

    def split(self) -> tuple[list[str], list[tuple[str, int]]] | None:
        """The lines of the text form read last, and the title and title line
        of each of its sections (None for a .ld file)."""
        if self.kind == LD_KIND:
            return None
        return self._text.lines, [(s.title, s.title_line) for s in self._text.sections]

    def read(self, text: str, edited: Edited | None = None) -> tuple[Program, list[Diagnostic]]:
        """`edited`: what the editor knows of the lines untouched since the
        last read (lang.textform.reader.Edited), or None."""
        if self.kind == LD_KIND:
            return parse(text, self.kind)
        return self._text.read(text, edited)


def format_read(text: str, program: Program, problems: list[Diagnostic], reflow: bool = False) -> str | None:
    """`lang.textform.formatter.format_text` for a text already read (by an
    IncrementalReader): the canonical text, or None when it has errors."""
    from lang.diagnostics import ERROR
    from lang.textform.formatter import existing_width, newline_of
    from lang.textform.writer import render_program

    if any(p.severity == ERROR for p in problems):
        return None
    formatted = render_program(program, None if reflow else existing_width(text))
    newline = newline_of(text)
    return formatted if newline == "\n" else formatted.replace("\n", newline)
