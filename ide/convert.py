"""Converting a program between the text form and LDmicro's `.ld`, the file
written beside its source (the editor's `ladder.convert`): a `.ld` in the
code page LDmicro reads, with CRLF line ends; a `.ladder` in UTF-8."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from lang.diagnostics import ERROR, Diagnostic
from lang.files import write_whole
from lang.loader import load_file
from lang.model import Program
from lang.values import encode_text

TARGETS = ("ladder", "ld")


class ConvertError(ValueError):
    """A conversion that cannot be made; the message is for the user."""


@dataclass(frozen=True)
class Converted:
    path: Path  # written
    warnings: tuple[str, ...]  # what the .ld file could not hold as it is


def convert(source: Path | None, target: object, encoding: str,
            read: tuple[Program, list[Diagnostic]] | None = None) -> Converted:
    """Write the program of `source` (as `read` already, else read from the
    file, LDmicro's files in `encoding`) beside it as `target`, "ladder" or "ld"."""
    if target not in TARGETS:
        raise ConvertError(f"target must be \"ladder\" or \"ld\", not {target!r}")
    if source is None:
        raise ConvertError("save the document to a file first: the converted file is written beside it")
    if read is None:
        try:
            loaded = load_file(source, encoding if source.suffix.lower() != ".ladder" else None)
        except OSError as problem:
            raise ConvertError(f"cannot read {source}: {problem.strerror or problem}") from problem
        read = loaded.program, loaded.diagnostics
    program, problems = read
    if any(p.severity == ERROR for p in problems):
        raise ConvertError(f"{source.name} has errors; fix them before converting")
    warnings: list[Diagnostic] = []
    if target == "ld":
        from lang.ldfile import write_ld

        out = source.with_suffix(".ld")
        text = write_ld(program, diagnostics=warnings)
        refused = [d.message for d in warnings if d.severity == ERROR]
        if refused:  # a pin the .ld cannot hold: no file LDmicro would refuse
            raise ConvertError("; ".join(refused))
        try:
            data = encode_text(text.replace("\n", "\r\n"), encoding)
        except UnicodeEncodeError as problem:
            raise ConvertError(f"{problem.object[problem.start]!r} cannot be written in {encoding}, the code page "
                               "of the .ld file; rename it or choose another ladder.encoding") from None
    else:
        from lang.textform.writer import render_program

        out = source.with_suffix(".ladder")
        data = encode_text(render_program(program), "utf-8")
    if out == source:
        raise ConvertError(f"{source.name} is already a {'.ld' if target == 'ld' else '.ladder'} file")
    try:
        write_whole(out, data)
    except OSError as problem:
        raise ConvertError(f"cannot write {out}: {problem.strerror or problem}") from problem
    return Converted(out, tuple(d.message for d in warnings))
