"""`ladder convert IN OUT`: between the text form and LDmicro's .ld."""

from __future__ import annotations

import sys
from pathlib import Path

from lang.loader import DEFAULT_CODEPAGE
from lang.textform.writer import render_program
from lang.values import encode_text

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, has_errors, load, report


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "convert", help="convert between .ladder/.txt and LDmicro .ld",
        description="Convert by extension: .ld to .ladder or .txt (LDmicro's export layout), "
                    ".ladder or .txt to .ld. Nothing is lost: what the drawing cannot show goes to the "
                    "SETTINGS and DETAILS sections.")
    parser.add_argument("source", metavar="IN")
    parser.add_argument("target", metavar="OUT")
    parser.add_argument("--encoding", help="encoding of the LDmicro file read (default cp1252)")
    parser.add_argument("--output-encoding", default=None,
                        help="encoding of the file written (default: UTF-8 for .ladder, cp1252 otherwise)")
    parser.set_defaults(func=run)


def run(args) -> int:
    loaded = load(args.source, args.encoding)
    if loaded is None:
        return EXIT_USAGE
    if has_errors(loaded.diagnostics):
        report(args.source, loaded.diagnostics, sys.stderr)
        return EXIT_PROBLEMS
    target = Path(args.target)
    suffix = target.suffix.lower()
    if suffix not in (".ld", ".ladder", ".txt"):
        print(f"{args.target}: error: the output must end in .ld, .ladder or .txt", file=sys.stderr)
        return EXIT_USAGE
    if suffix == ".ld":
        from lang.ldfile import write_ld

        text, newline, encoding = write_ld(loaded.program), "\r\n", args.output_encoding or DEFAULT_CODEPAGE
    else:
        text = render_program(loaded.program)
        ladder = suffix == ".ladder"
        newline = "\n" if ladder else "\r\n"
        encoding = args.output_encoding or ("utf-8" if ladder else DEFAULT_CODEPAGE)
    target.write_bytes(encode_text(text.replace("\n", newline), encoding))
    return EXIT_OK
