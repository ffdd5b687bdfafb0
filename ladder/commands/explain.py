"""`ladder explain CODE`: what a diagnostic means."""

from __future__ import annotations

import sys

from lang.codes import CODES

from ._common import EXIT_OK, EXIT_USAGE


def register(subparsers) -> None:
    parser = subparsers.add_parser("explain", help="explain a diagnostic code",
                                   description="Print the documentation of a diagnostic code (e.g. LD101); "
                                               "without a code, list them all.")
    parser.add_argument("code", nargs="?", metavar="CODE")
    parser.set_defaults(func=run)


def run(args) -> int:
    import lang.checks  # noqa: F401  (the checks and the simulator register their codes)
    import compiler.errors  # noqa: F401
    import lang.sim.errors  # noqa: F401

    if args.code is None:
        for code in sorted(CODES.values(), key=lambda c: c.code):
            print(f"{code.code}  {code.summary}")
        return EXIT_OK
    code = CODES.get(args.code.upper())
    if code is None:
        print(f"ladder explain: unknown code {args.code!r}; `ladder explain` lists them", file=sys.stderr)
        return EXIT_USAGE
    print(f"{code.code}: {code.summary}\n\n{code.doc}")
    return EXIT_OK
