"""`ladder check FILE...`: every problem, one line each."""

from __future__ import annotations

import sys
from pathlib import Path

from lang import codes, config

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, add_encoding, has_errors, load, report


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "check", help="report problems as path:line:col: severity CODE message",
        description="Check ladder programs. Exit 0 when clean (warnings allowed), 1 when errors were found, "
                    "2 when a file cannot be read.")
    parser.add_argument("files", nargs="+", metavar="FILE")
    add_encoding(parser)
    parser.set_defaults(func=run)


def run(args) -> int:
    from lang.checks import check_program

    status = EXIT_OK
    for path in args.files:
        loaded = load(path, args.encoding)
        if loaded is None:
            status = EXIT_USAGE
            continue
        diagnostics = list(loaded.diagnostics)
        if any(d.code == codes.UNREADABLE for d in diagnostics):
            report(path, diagnostics)
            status = EXIT_USAGE
            continue
        if not has_errors(diagnostics):
            try:
                diagnostics += check_program(loaded.program, severities=config.find(Path(path)))
            except config.ConfigError as bad:
                print(f"ladder check: {bad}", file=sys.stderr)
                return EXIT_USAGE
        report(path, diagnostics)
        if has_errors(diagnostics) and status == EXIT_OK:
            status = EXIT_PROBLEMS
    return status
