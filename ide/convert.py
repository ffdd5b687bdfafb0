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
    if source is None:
        raise ConvertError("save the document to a file first: the converted file is written beside it")
    if read is None:
        try:
            loaded = load_file(source, encoding if source.suffix.lower() != ".ladder" else None)
        except OSError as problem:
            raise ConvertError(f"cannot read {source}: {problem.strerror or problem}") from problem
        read = loaded.program, loaded.diagnostics
    program, problems = read
    made = render(program, problems, target, encoding, source.name)
    out = source.with_suffix(made.suffix)
    if out == source:
        raise ConvertError(f"{source.name} is already a {made.suffix} file")
    try:
        write_whole(out, made.data)
    except OSError as problem:
        raise ConvertError(f"cannot write {out}: {problem.strerror or problem}") from problem
    return Converted(out, made.warnings)


@dataclass(frozen=True)
class Rendered:
    suffix: str  # ".ladder" or ".ld"
    data: bytes  # the file's contents
    warnings: tuple[str, ...]


def render(program: Program, problems: list[Diagnostic], target: object, encoding: str, name: str) -> Rendered:
    """The file's contents as `target` ("ladder" or "ld") of the program read
    from `name` with `problems`: written beside the source by `convert`,
    handed to the browser as a download."""
    if target not in TARGETS:
        raise ConvertError(f"target must be \"ladder\" or \"ld\", not {target!r}")
    if any(p.severity == ERROR for p in problems):
        raise ConvertError(f"{name} has errors; fix them before converting")
    warnings: list[Diagnostic] = []
    if target == "ld":
        from lang.ldfile import write_ld

        text = write_ld(program, diagnostics=warnings)
        refused = [d.message for d in warnings if d.severity == ERROR]
        if refused:  # a pin the .ld cannot hold: no file LDmicro would refuse
            raise ConvertError("; ".join(refused))
        try:
            data = encode_text(text.replace("\n", "\r\n"), encoding)
        except UnicodeEncodeError as problem:
            raise ConvertError(f"{problem.object[problem.start]!r} cannot be written in {encoding}, the code page "
                               "of the .ld file; rename it or choose another ladder.encoding") from None
        return Rendered(".ld", data, tuple(d.message for d in warnings))
    from lang.textform.writer import render_program

    return Rendered(".ladder", encode_text(render_program(program), "utf-8"), ())
