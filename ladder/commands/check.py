"""`ladder check FILE...`: every problem, one line each. When the checks
find no error and a back end compiles the program's part, the program is
compiled too (not written), for what only the compiler knows: a program too
large for the part's flash (LD703) or RAM (LD704)."""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

from ide.fixes import fix_all
from lang import codes, config
from lang.devices import find_device
from lang.families import compiled
from lang.loader import Loaded, checkable, checked, kind_of, parse
from lang.values import encode_text

from ._common import EXIT_OK, EXIT_PROBLEMS, EXIT_USAGE, add_encoding, has_errors, load, report, write_output


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "check", help="report problems as path:line:col: severity CODE message",
        description="Check ladder programs. Exit 0 when clean (warnings allowed), 1 when errors were found, "
                    "2 when a file cannot be read.")
    parser.add_argument("files", nargs="+", metavar="FILE", help="a program, or - to read one from stdin")
    parser.add_argument("--fix", action="store_true",
                        help="make the fixes that need no choice (a timer named 'delay' becomes 'Tdelay'), "
                             "write the file back and report what remains")
    add_encoding(parser)
    parser.set_defaults(func=run)


def run(args) -> int:
    from lang.checks import check_program

    status = EXIT_OK
    for path in args.files:
        if path == "-" and args.fix:
            print("ladder check: error: --fix rewrites files; it cannot fix stdin", file=sys.stderr)
            return EXIT_USAGE
        loaded = _stdin() if path == "-" else load(path, args.encoding)
        path = "<stdin>" if path == "-" else path
        if loaded is None:
            status = EXIT_USAGE
            continue
        diagnostics = list(loaded.diagnostics)
        if any(d.code == codes.UNREADABLE for d in diagnostics):
            report(path, diagnostics)
            status = EXIT_USAGE
            continue
        if checkable(loaded.program, diagnostics):
            try:
                severities = config.find(Path(path))
            except config.ConfigError as bad:
                print(f"ladder check: {bad}", file=sys.stderr)
                return EXIT_USAGE
            if args.fix:
                loaded = _fixed(path, loaded, severities) or loaded
                diagnostics = list(loaded.diagnostics)
            if checkable(loaded.program, diagnostics):
                diagnostics += checked(loaded.program, check_program(loaded.program, severities=severities))
                if not has_errors(diagnostics):
                    diagnostics += _size_problems(loaded.program, severities)
        report(path, diagnostics)
        if has_errors(diagnostics) and status == EXIT_OK:
            status = EXIT_PROBLEMS
    return status


def _size_problems(program, severities) -> list:
    """Flash and RAM that the program's part does not have (LD703, LD704):
    the compiler decides, so it compiles the program as `ladder build` would."""
    device = find_device(program.settings.mcu) if program.settings.mcu else None
    if device is None or not compiled(device):
        return []
    from compiler import size_problems

    return severities.apply(size_problems(program))


def _stdin() -> Loaded:
    """A program piped in (like `ladder fmt -`): its kind from its first line."""
    text = sys.stdin.read()
    kind = kind_of("-", text)
    program, problems = parse(text, kind)
    return Loaded(program, problems, kind, text, "utf-8")


def _fixed(path: str, loaded: Loaded, severities) -> Loaded | None:
    """The file after `--fix`, written back and read again (None: nothing fixed)."""
    text, applied = fix_all(loaded.text, loaded.kind, severities)
    if not applied:
        return None
    if not write_output(path, encode_text(text, loaded.encoding)):
        return None
    for title in applied:
        print(f"{path}: fixed: {title}", file=sys.stderr)
    program, problems = parse(text, loaded.kind)
    return replace(loaded, program=program, diagnostics=problems, text=text)
