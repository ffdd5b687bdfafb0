"""`ladder convert IN OUT`: between the text form and LDmicro's .ld."""

from __future__ import annotations

import codecs
import sys
from pathlib import Path

from lang.codes import code
from lang.diagnostics import Diagnostic
from lang.diagnostics import report as diagnostic
from lang.loader import DEFAULT_CODEPAGE
from lang.model import Span
from lang.textform.writer import render_program
from lang.values import encode_text

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, has_errors, load, report, write_output

UNENCODABLE = code("LD012")


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "convert", help="convert between .ladder/.txt and LDmicro .ld",
        description="Convert by extension: .ld to .ladder or .txt (LDmicro's export layout), "
                    ".ladder or .txt to .ld. Nothing is lost: what the drawing cannot show goes to the "
                    "SETTINGS and DETAILS sections. An existing OUT is replaced only with --force, and "
                    "never the input itself.")
    parser.add_argument("source", metavar="IN")
    parser.add_argument("target", metavar="OUT")
    parser.add_argument("--encoding", help="encoding of the LDmicro file read (default cp1252)")
    parser.add_argument("--output-encoding", default=None,
                        help="encoding of the file written (default: UTF-8 for .ladder, cp1252 otherwise)")
    parser.add_argument("--force", action="store_true", help="replace OUT if it exists")
    parser.set_defaults(func=run)


def run(args) -> int:
    target = Path(args.target)
    suffix = target.suffix.lower()
    if suffix not in (".ld", ".ladder", ".txt"):
        print(f"{args.target}: error: the output must end in .ld, .ladder or .txt", file=sys.stderr)
        return EXIT_USAGE
    if args.output_encoding is not None:
        try:
            codecs.lookup(args.output_encoding)
        except LookupError:
            print(f"ladder convert: error: unknown encoding {args.output_encoding!r} (e.g. cp1252, cp1251, "
                  "utf-8)", file=sys.stderr)
            return EXIT_USAGE
    if target.exists():
        if Path(args.source).exists() and target.resolve() == Path(args.source).resolve():
            print(f"{args.target}: error: the output is the input; convert writes a new file", file=sys.stderr)
            return EXIT_USAGE
        if not args.force:
            print(f"{args.target}: error: the file exists; use --force to replace it", file=sys.stderr)
            return EXIT_USAGE
    loaded = load(args.source, args.encoding)
    if loaded is None:
        return EXIT_USAGE
    if has_errors(loaded.diagnostics):
        report(args.source, loaded.diagnostics, sys.stderr)
        return EXIT_PROBLEMS
    warnings: list[Diagnostic] = []
    if suffix == ".ld":
        from lang.ldfile import write_ld

        text, newline = write_ld(loaded.program, diagnostics=warnings), "\r\n"
        encoding = args.output_encoding or DEFAULT_CODEPAGE
    else:
        text = render_program(loaded.program)
        ladder = suffix == ".ladder"
        newline = "\n" if ladder else "\r\n"
        encoding = args.output_encoding or ("utf-8" if ladder else DEFAULT_CODEPAGE)
    if has_errors(warnings):  # a pin the .ld cannot hold: no file LDmicro would refuse
        report(args.source, warnings, sys.stderr)
        return EXIT_PROBLEMS
    try:
        data = encode_text(text.replace("\n", newline), encoding)
    except UnicodeEncodeError as problem:
        report(args.source, [_unencodable(loaded.text, problem.object[problem.start], encoding)], sys.stderr)
        return EXIT_PROBLEMS
    report(args.source, warnings, sys.stderr)
    return EXIT_OK if write_output(target, data) else EXIT_USAGE


def _unencodable(source: str, char: str, encoding: str) -> Diagnostic:
    """The error for a character the output encoding lacks, at its first place in the source."""
    where = source.find(char)
    line = source.count("\n", 0, where) if where >= 0 else 0
    col = where - (source.rfind("\n", 0, where) + 1) if where >= 0 else 0
    return diagnostic(UNENCODABLE, f"{char!r} (U+{ord(char):04X}) cannot be written in {encoding}, the "
                                   f"code page of the file written; rename it, or choose another code page with "
                                   f"--output-encoding (LDmicro reads the file in its Windows code page)",
                      Span.at(line, col, col + 1) if where >= 0 else None)
