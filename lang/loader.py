"""Reading any program file: `.ladder` (UTF-8), LDmicro exports (`.txt`
starting `LDmicro export text`) and LDmicro `.ld` files (8-bit code page).
The one entry point the command line, the simulator and the language server
share."""

from __future__ import annotations

import sys
from bisect import bisect_right
from dataclasses import dataclass
from pathlib import Path

from . import codes
from .diagnostics import ERROR, Diagnostic, error
from .model import Program, Span
from .values import decode_bytes

DEFAULT_CODEPAGE = "cp1252"
TEXT_KIND = "ladder"
LD_KIND = "ld"


@dataclass
class Loaded:
    program: Program
    diagnostics: list[Diagnostic]
    kind: str  # TEXT_KIND or LD_KIND
    text: str
    encoding: str


def kind_of(path: str | Path, text: str = "") -> str:
    """By extension; a `.txt` or unknown file by its first line."""
    suffix = Path(path).suffix.lower()
    if suffix == ".ld":
        return LD_KIND
    if suffix == ".ladder":
        return TEXT_KIND
    return LD_KIND if text.startswith("LDmicro0.") else TEXT_KIND


def encoding_for(path: str | Path, encoding: str | None) -> str:
    """`.ladder` is UTF-8; LDmicro's files are in the Windows code page."""
    if encoding:
        return encoding
    return "utf-8" if Path(path).suffix.lower() == ".ladder" else DEFAULT_CODEPAGE


def parse(text: str, kind: str) -> tuple[Program, list[Diagnostic]]:
    if kind == LD_KIND:
        from .ldfile import read_ld

        return read_ld(text)
    from .textform.reader import read_text

    return read_text(text)


def checkable(program: Program, problems: list[Diagnostic]) -> bool:
    """Whether the checks can run on a program read with these problems: it
    was read without error, or every reading error is inside a rung the text
    reader could not read (that rung stands in its place, and the checks say
    nothing inside it: `checked`). An error anywhere else (the header, the
    I/O table, DETAILS, an .ld file) leaves the program too incomplete to
    check without false alarms."""
    errors = [p for p in problems if p.severity == ERROR]
    if not errors:
        return True
    unread = _unread_lines(program)
    return all(p.span is not None and _inside(p.span.line, unread) for p in errors)


def checked(program: Program, diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    """The checks' diagnostics without those inside rungs that could not be
    read: a half-read rung's structure is not what was drawn."""
    unread = _unread_lines(program)
    if not unread:
        return diagnostics
    return [d for d in diagnostics if d.span is None or not _inside(d.span.line, unread)]


def _unread_lines(program: Program) -> list[tuple[int, int]]:
    from .textform.rungs import UnreadRung

    return [(rung.span.line, rung.span.end_line) for rung in program.rungs
            if isinstance(rung, UnreadRung) and rung.span is not None]


def _inside(line: int, ranges: list[tuple[int, int]]) -> bool:
    at = bisect_right(ranges, (line, sys.maxsize)) - 1
    return at >= 0 and ranges[at][0] <= line <= ranges[at][1]


def decode(data: bytes, path: str | Path, encoding: str | None) -> tuple[str, str, list[Diagnostic]]:
    """The text of a file; bytes that are not valid in the encoding become a
    located error, never a traceback (and are kept, for `.ld` code pages)."""
    chosen = encoding_for(path, encoding)
    if b"\x00" in data[:4096]:
        return "", chosen, [error(codes.UNREADABLE, "this is a binary file, not a ladder program", Span.at(0, 0))]
    try:
        if chosen.replace("-", "").lower() != "utf8":
            return decode_bytes(data, chosen), chosen, []
        return data.decode(chosen), chosen, []
    except UnicodeDecodeError as problem:
        line = data[:problem.start].count(b"\n")
        col = problem.start - (data.rfind(b"\n", 0, problem.start) + 1)
        text = data.decode(chosen, errors="replace")
        return text, chosen, [error(codes.UNREADABLE, f"byte 0x{data[problem.start]:02X} is not valid {chosen}; "
                                    "give the file's encoding with --encoding", Span.at(line, col))]
    except LookupError:
        return "", chosen, [error(codes.UNREADABLE, f"unknown encoding {chosen!r}", None)]


def load_bytes(data: bytes, path: str | Path, encoding: str | None = None) -> Loaded:
    text, chosen, problems = decode(data, path, encoding)
    if problems and not text:
        return Loaded(Program(), problems, kind_of(path), text, chosen)
    kind = kind_of(path, text)
    program, found = parse(text, kind)
    return Loaded(program, problems + found, kind, text, chosen)


def load_path(path: str | Path, encoding: str | None = None) -> tuple[Program, list[Diagnostic]]:
    """Read a program file; OSError if it cannot be opened."""
    loaded = load_file(path, encoding)
    return loaded.program, loaded.diagnostics


def load_file(path: str | Path, encoding: str | None = None) -> Loaded:
    return load_bytes(Path(path).read_bytes(), path, encoding)
