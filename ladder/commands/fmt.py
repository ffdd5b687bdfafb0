"""`ladder fmt FILE...`: rewrite files in the canonical layout."""

from __future__ import annotations

import difflib
import sys

from lang.loader import LD_KIND
from lang.textform.formatter import format_text
from lang.values import encode_text

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, add_encoding, load, report, write_output


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "fmt", help="format files in LDmicro's layout",
        description="Rewrite .ladder (and LDmicro .txt export) files in the canonical layout. A file with "
                    "errors is left untouched. `-` formats standard input to standard output.")
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if a file would change")
    parser.add_argument("--diff", action="store_true", help="print a unified diff instead of writing")
    parser.add_argument("--reflow", action="store_true",
                        help="re-align every rung to the widest one instead of keeping the file's width")
    add_encoding(parser)
    parser.set_defaults(func=run)


def run(args) -> int:
    status = EXIT_OK
    for path in args.files:
        if path == "-":
            text = sys.stdin.read()
            formatted, problems = format_text(text, args.reflow)
            if formatted is None:
                report("<stdin>", problems, sys.stderr)
                return EXIT_PROBLEMS
            sys.stdout.write(formatted)
            continue
        loaded = load(path, args.encoding)
        if loaded is None:
            status = EXIT_USAGE
            continue
        if loaded.kind == LD_KIND:
            print(f"{path}: error: fmt formats the text form; use `ladder convert` for .ld files",
                  file=sys.stderr)
            status = EXIT_USAGE
            continue
        formatted, problems = format_text(loaded.text, args.reflow)
        if formatted is None:
            report(path, problems, sys.stderr)
            status = max(status, EXIT_PROBLEMS)
            continue
        if formatted == loaded.text:
            continue
        if args.diff:
            sys.stdout.writelines(difflib.unified_diff(
                loaded.text.splitlines(keepends=True), formatted.splitlines(keepends=True),
                fromfile=path, tofile=path))
        if args.check or args.diff:
            if args.check:
                print(f"{path}: would be reformatted", file=sys.stderr)
            status = max(status, EXIT_PROBLEMS) if args.check else status
            continue
        if not write_output(path, encode_text(formatted, loaded.encoding)):
            status = EXIT_USAGE
    return status
