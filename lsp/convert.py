"""The `ladder.convert` and `ladder.build` commands (docs/lsp-protocol.md),
and `ladder.compileOnSave`: convert the document between the text form and
LDmicro's `.ld` (ide.convert), writing the file beside the source; compile it with the
compiler (`ladder build`), the HEX file beside the source: on request, or on
save when `lang.families` says a back end compiles the program's part. The
compiler's errors and warnings (LD501 is an error there; LD712 when a scan
may not fit the cycle, on the rung that takes the most) join the document's
diagnostics until its next change. The summary ends with the scan's worst
case (`scan: at most N cycles = T µs of the C ms cycle (P%)`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from lsprotocol import types

from ide.convert import ConvertError, convert
from lang.devices import find_device
from lang.families import compiled

from .documents import file_path
from .protocol import UserError

if TYPE_CHECKING:
    from .server import LadderServer


def _uri_argument(args: Sequence[object]) -> str:
    if not args or not isinstance(args[0], str):
        raise UserError("the first argument must be the document's URI")
    return args[0]


# a server in a browser (lsp/worker.py) has no disk to write beside the document
NO_DISK = "in the browser no file is written beside the document: ladder.export gives the {what} to download"


def convert_document(ls: LadderServer, uri: str, target: object) -> dict[str, str]:
    if not ls.writes_files:
        raise UserError(NO_DISK.format(what="converted file"))
    analysis = ls.documents.analysis(uri)
    try:
        done = convert(file_path(uri), target, ls.settings.encoding,
                       (analysis.program, analysis.problems) if analysis is not None else None)
    except ConvertError as problem:
        raise UserError(str(problem)) from problem
    if done.warnings:
        ls.window_show_message(types.ShowMessageParams(type=types.MessageType.Warning,
                                                       message="; ".join(done.warnings)))
    return {"path": str(done.path)}


def register(server: LadderServer) -> None:
    @server.on_command("ladder.convert")
    def convert_command(ls: LadderServer, *args: object) -> dict[str, str]:
        uri = _uri_argument(args)
        target = args[1] if len(args) > 1 else None
        if isinstance(target, dict):  # {"target": "ld"} is accepted too
            target = target.get("target")
        return convert_document(ls, uri, target)

    @server.on_command("ladder.build")
    def build_command(ls: LadderServer, *args: object) -> dict[str, Any]:
        return build(ls, _uri_argument(args))

    def saved(ls: LadderServer, uri: str | None) -> None:
        if not ls.settings.compile_on_save or uri is None:
            return
        if not ls.writes_files:
            ls.log("compile on save: " + NO_DISK.format(what="HEX file"), types.MessageType.Warning)
            return
        analysis = ls.documents.analysis(uri)
        if analysis is None or analysis.has_errors or not analysis.program.settings.mcu:
            return
        device = find_device(analysis.program.settings.mcu)
        if device is None or not compiled(device):
            return
        result = build(ls, uri)
        kind = types.MessageType.Info if result["ok"] else types.MessageType.Warning
        ls.log(f"compile on save: {result['summary']}" + (f" -> {result['hex']}" if result["hex"] else ""), kind)

    server.subscribe("saved", saved)


def build(ls: LadderServer, uri: str) -> dict[str, Any]:
    """Compile the document's program to a HEX file beside it (`ladder build`)."""
    if not ls.writes_files:
        raise UserError(NO_DISK.format(what="HEX file"))
    analysis = ls.documents.analysis(uri)
    if analysis is None:
        raise UserError("not a ladder document")
    source = file_path(uri)
    if source is None:
        raise UserError("save the document to a file first: the HEX file is written beside it")
    publisher = ls.diagnostics
    if analysis.has_errors:
        return {"ok": False, "summary": "the program has errors; fix them before building", "hex": None}
    import compiler
    from compiler.errors import CompileError

    try:
        result = compiler.build(analysis.program)
    except CompileError as problem:
        if publisher is not None:
            publisher.set_extra(uri, problem.diagnostics)
        shown = "; ".join(d.message for d in problem.diagnostics[:3])
        more = len(problem.diagnostics) - 3
        return {"ok": False, "summary": shown + (f" (and {more} more)" if more > 0 else ""), "hex": None}
    out = source.with_suffix(".hex")
    try:
        result.write(out)
    except OSError as problem:
        raise UserError(f"cannot write {out}: {problem.strerror or problem}") from problem
    if publisher is not None:
        publisher.set_extra(uri, result.warnings)
    summary = result.summary() + (f"; {result.budget.summary()}" if result.budget is not None else "")
    return {"ok": True, "summary": summary, "hex": str(out)}
