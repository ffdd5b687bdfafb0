"""`ladder` — one command, one subcommand per feature.

Each subcommand lives in its own module under `ladder/commands/` and exposes
`register(subparsers)`, which adds its parser and sets `func(args) -> int`.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from importlib import metadata

COMMANDS = ("check", "fmt", "convert", "dump", "explain", "parts", "new", "sim", "test", "verify", "build", "lsp")


def _version() -> str:
    try:
        return metadata.version("textladder")
    except metadata.PackageNotFoundError:  # run from a checkout that is not installed
        return "(not installed)"


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="ladder",
        description="Ladder logic as plain text: check, format, convert, simulate and compile LDmicro programs.",
    )
    parser.add_argument("--version", action="version", version=f"ladder {_version()}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    subparsers.required = True
    for name in COMMANDS:
        importlib.import_module(f"ladder.commands.{name}").register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except BrokenPipeError:
        return 0
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
