"""`ladder build FILE`: compile a program for a part `lang.targets` lists.

On success prints `PART: flash N/M bytes (P%), RAM N/M bytes (P%)` (flash in
words for PIC) and the scan's worst case, `scan: at most N cycles = T µs of
the C ms cycle (P%)` (compiler/budget.py), and writes the Intel HEX (default:
beside FILE, same stem) and the assembly listing beside the HEX (the back
end's suffix: .lst for AVR). Problems are `path:line:col: error CODE message`
lines and exit 1; warnings go to stderr and do not stop the build.
"""

from __future__ import annotations

import sys
from pathlib import Path

from lang import codes, config
from lang.devices import find_device
from lang.targets import compiled, parts_text

from ._common import (
    EXIT_OK,
    EXIT_PROBLEMS,
    EXIT_USAGE,
    add_encoding,
    has_errors,
    load,
    report,
)


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "build", help="compile a program to an Intel HEX file",
        description=f"Compile a ladder program for one of these parts: {parts_text()}. Writes OUT.hex and "
                    "the listing beside it (OUT.lst for AVR); exit 1 on errors, 2 when FILE cannot be read.")
    parser.add_argument("file", metavar="FILE")
    parser.add_argument("-o", "--output", metavar="OUT.hex", help="the HEX file to write (default: FILE with .hex)")
    parser.add_argument("--target", metavar="PART",
                        help="compile for this part instead of the program's (LDmicro name or short name, "
                             "e.g. atmega328p); pins given by port name carry over, package pin numbers "
                             "must exist on the new part")
    add_encoding(parser)
    parser.set_defaults(func=run)


def run(args) -> int:
    import compiler
    from compiler.errors import CompileError

    if args.target is not None:
        device = find_device(args.target)
        if device is None or not compiled(device):
            known = "unknown part" if device is None else "a part ladder build does not compile"
            print(f"ladder build: error: --target {args.target}: {known}; it compiles for {parts_text()}",
                  file=sys.stderr)
            return EXIT_USAGE
    loaded = load(args.file, args.encoding)
    if loaded is None:
        return EXIT_USAGE
    if any(d.code == codes.UNREADABLE for d in loaded.diagnostics):
        report(args.file, loaded.diagnostics, stream=sys.stdout)
        return EXIT_USAGE
    if has_errors(loaded.diagnostics):
        report(args.file, loaded.diagnostics, stream=sys.stdout)
        return EXIT_PROBLEMS
    try:
        build = compiler.build(loaded.program, args.target, config.find(Path(args.file)))
    except config.ConfigError as bad:
        print(f"ladder build: {bad}", file=sys.stderr)
        return EXIT_USAGE
    except CompileError as problem:
        report(args.file, problem.diagnostics, stream=sys.stdout)
        return EXIT_PROBLEMS
    report(args.file, build.warnings, stream=sys.stderr)
    output = Path(args.output) if args.output else Path(args.file).with_suffix(".hex")
    try:
        build.write(output)
    except OSError as problem:
        print(f"{problem.filename or output}: error: cannot write: {problem.strerror or problem}", file=sys.stderr)
        return EXIT_USAGE
    print(build.summary())
    if build.budget is not None:
        print(build.budget.summary())
    return EXIT_OK
