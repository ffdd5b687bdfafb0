"""`ladder.export`: the files a program makes, handed to the client instead
of written beside the document, for a server that has no disk of its own
(lsp/worker.py). Each file is `{"name", "data"}`, its bytes in base64: a
`.ld` is in LDmicro's code page (`ladder.encoding`), not UTF-8.

Targets: "ladder" and "ld" (ide.convert), "c" (the portable C, `ladder build
--emit c`: FILE.c, FILE.h and a ladder.h to start from), "hex" (the part's image, `ladder build`; its
summary with the scan's worst case as the answer's `summary`)."""

from __future__ import annotations

import base64
from pathlib import PurePosixPath
from typing import TYPE_CHECKING, Any

from pygls import uris

from ide.convert import ConvertError, render

from .protocol import UserError

if TYPE_CHECKING:
    from .server import LadderServer

TARGETS = ("ladder", "ld", "c", "hex")
Json = dict[str, Any]


def stem_of(uri: str) -> str:
    """The document's name without its suffix (`untitled:Untitled-1`,
    `inmemory://model/blink.ladder`...), "program" when it names nothing."""
    name = PurePosixPath(uris.urlparse(uri)[2].replace("\\", "/")).name
    stem = PurePosixPath(name).stem if "." in name else name
    return stem or "program"


def _file(name: str, data: bytes) -> Json:
    return {"name": name, "data": base64.b64encode(data).decode("ascii")}


def export(ls: LadderServer, uri: str, target: object) -> Json:
    if target not in TARGETS:
        raise UserError(f"target must be one of {', '.join(TARGETS)}, not {target!r}")
    analysis = ls.documents.analysis(uri)
    if analysis is None:
        raise UserError("not a ladder document")
    stem = stem_of(uri)
    if target in ("ladder", "ld"):
        try:
            made = render(analysis.program, analysis.problems, target, ls.settings.encoding, stem)
        except ConvertError as problem:
            raise UserError(str(problem)) from problem
        return {"files": [_file(stem + made.suffix, made.data)], "summary": "", "warnings": list(made.warnings)}
    if analysis.has_errors:
        raise UserError("the program has errors; fix them before building")
    import compiler
    from compiler.errors import CompileError

    try:
        if target == "c":
            from compiler.c import default_ladder_h

            sources = compiler.build_c(analysis.program, stem, stem + ".ladder")
            texts = ((stem + ".c", sources.c), (stem + ".h", sources.h), ("ladder.h", default_ladder_h()))
            return {"files": [_file(name, text.encode("utf-8")) for name, text in texts], "summary": "", "warnings": []}
        result = compiler.build(analysis.program)
    except CompileError as problem:
        if ls.diagnostics is not None:  # shown where they are, as ladder.build does
            ls.diagnostics.set_extra(uri, problem.diagnostics)
        raise UserError("; ".join(d.message for d in problem.diagnostics[:3])) from problem
    summary = result.summary() + (f"; {result.budget.summary()}" if result.budget is not None else "")
    return {"files": [_file(stem + ".hex", result.image.hex().encode("ascii"))], "summary": summary,
            "warnings": [d.message for d in result.warnings]}


def register(server: LadderServer) -> None:
    @server.on_command("ladder.export")
    def export_command(ls: LadderServer, *args: object) -> Json:
        if not args or not isinstance(args[0], str):
            raise UserError("the first argument must be the document's URI")
        target: object = args[1] if len(args) > 1 else None
        if isinstance(target, dict):  # {"target": "hex"} is accepted too, as ladder.convert does
            target = target.get("target")
        return export(ls, args[0], target)
