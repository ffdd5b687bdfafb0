"""What the subcommands share: reading files and reporting problems."""

from __future__ import annotations

import sys
from pathlib import Path

from lang.diagnostics import ERROR, Diagnostic
from lang.files import write_whole
from lang.loader import Loaded, load_file

EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE = 0, 1, 2


def add_encoding(parser) -> None:
    parser.add_argument("--encoding", help="encoding of LDmicro files (default cp1252; .ladder files are UTF-8)")


def load(path: str, encoding: str | None) -> Loaded | None:
    """The file read, or None after saying why it cannot be read."""
    try:
        return load_file(path, encoding)
    except OSError as problem:
        print(f"{path}: error: {problem.strerror or problem}", file=sys.stderr)
        return None


def report(path: str, diagnostics: list[Diagnostic], stream=None) -> None:
    """Print the diagnostics in source order (to stdout by default: the
    stream of the moment, not the one at import)."""
    for diagnostic in sorted(diagnostics, key=lambda d: (d.span is None, d.span or 0, d.code)):
        print(diagnostic.format(path), file=stream or sys.stdout)


def has_errors(diagnostics: list[Diagnostic]) -> bool:
    return any(d.severity == ERROR for d in diagnostics)


def write_output(path: str | Path, data: bytes) -> bool:
    """Write a file whole (lang.files), creating the folders it names that do
    not exist yet (as `-o build/x.hex` users expect); False after `path:
    error: cannot write: reason`, the one message every command gives."""
    return writing(path, lambda: write_whole(path, data))


def writing(path: str | Path, write) -> bool:
    """Run `write()` once the folders of `path` exist; False after the
    message `write_output` gives when a folder or the file cannot be made."""
    try:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write()
    except OSError as problem:
        print(f"{problem.filename or path}: error: cannot write: {problem.strerror or problem}", file=sys.stderr)
        return False
    return True
