"""`ladder dump FILE`: the model as JSON."""

from __future__ import annotations

import sys

from lang.dump import dumps

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, add_encoding, has_errors, load, report


def register(subparsers) -> None:
    parser = subparsers.add_parser("dump", help="print the program model as JSON",
                                   description="Print the program model as JSON (with a \"version\" field).")
    parser.add_argument("file", metavar="FILE")
    add_encoding(parser)
    parser.set_defaults(func=run)


def run(args) -> int:
    loaded = load(args.file, args.encoding)
    if loaded is None:
        return EXIT_USAGE
    if has_errors(loaded.diagnostics):
        report(args.file, loaded.diagnostics, sys.stderr)
        return EXIT_PROBLEMS
    sys.stdout.write(dumps(loaded.program))
    return EXIT_OK
