"""`ladder lsp`: the language server, speaking LSP over stdio (docs/lsp.md)."""

from __future__ import annotations


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "lsp", help="run the language server (LSP over stdio)",
        description="Run the ladder language server on standard input and output, for editors "
                    "(VS Code, Neovim...). docs/lsp.md lists its features and settings.")
    parser.add_argument("--stdio", action="store_true", help="accepted for editors that pass it; stdio is the default")
    parser.add_argument("--log-file", metavar="PATH", help="write the server's log to this file instead of stderr")
    parser.add_argument("-v", "--verbose", action="store_true", help="log every message (debug level)")
    parser.set_defaults(func=run)


def run(args) -> int:
    from lsp.server import main

    return main(log_file=args.log_file, verbose=args.verbose)
