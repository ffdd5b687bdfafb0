"""`ladder explain CODE`: what a diagnostic means."""

from __future__ import annotations

import sys

from lang.codes import CODES
from lang.codes_doc import ldmicro_note

from ._common import EXIT_OK, EXIT_USAGE


def register(subparsers) -> None:
    parser = subparsers.add_parser("explain", help="explain a diagnostic code",
                                   description="Print the documentation of a diagnostic code (e.g. LD101); "
                                               "without a code, list them all.")
    parser.add_argument("code", nargs="?", metavar="CODE")
    parser.set_defaults(func=run)


def run(args) -> int:
    if args.code is None:
        for row in sorted(CODES.values(), key=lambda c: c.code):
            print(f"{row.code}  {row.severity:<7}  {row.summary}")
        return EXIT_OK
    code = CODES.get(args.code.upper())
    if code is None:
        print(f"ladder explain: unknown code {args.code!r}; `ladder explain` lists them", file=sys.stderr)
        return EXIT_USAGE
    print(f"{code.code}: {code.summary} ({code.severity}; {code.group})\n\n{code.doc}")
    note = ldmicro_note(code)
    if note:
        print(f"\n{note}")
    return EXIT_OK
