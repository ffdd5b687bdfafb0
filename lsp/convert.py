"""The `ladder.convert` and `ladder.build` commands (docs/lsp-protocol.md),
and `ladder.compileOnSave`: convert the document between the text form and
LDmicro's `.ld`, writing the file beside the source; compile it with the
compiler (`ladder build`), the HEX file beside the source: on request, or on
save when `lang.targets` says a back end compiles the program's part. The
compiler's errors and warnings (LD501 is an error there; LD712 when a scan
may not fit the cycle, on the rung that takes the most) join the document's
diagnostics until its next change. The summary ends with the scan's worst
case (`scan: at most N cycles = T µs of the C ms cycle (P%)`)."""

from __future__ import annotations

from lsprotocol import types

from lang.devices import find_device
from lang.files import write_whole
from lang.loader import load_file
from lang.targets import compiled
from lang.values import encode_text

from .documents import file_path
from .protocol import UserError


def _uri_argument(args) -> str:
    if not args or not isinstance(args[0], str):
        raise UserError("the first argument must be the document's URI")
    return args[0]


def convert(ls, uri: str, target: object) -> dict:
    if target not in ("ladder", "ld"):
        raise UserError(f"target must be \"ladder\" or \"ld\", not {target!r}")
    source = file_path(uri)
    if source is None:
        raise UserError("save the document to a file first: the converted file is written beside it")
    analysis = ls.documents.analysis(uri)
    if analysis is not None:
        program, problems = analysis.program, analysis.problems
    else:
        try:
            loaded = load_file(source, ls.settings.encoding if source.suffix.lower() != ".ladder" else None)
        except OSError as problem:
            raise UserError(f"cannot read {source}: {problem.strerror or problem}") from problem
        program, problems = loaded.program, loaded.diagnostics
    if any(p.severity == "error" for p in problems):
        raise UserError(f"{source.name} has errors; fix them before converting")
    if target == "ld":
        from lang.ldfile import write_ld

        out = source.with_suffix(".ld")
        long_lines: list = []
        text = write_ld(program, diagnostics=long_lines)
        refused = [d.message for d in long_lines if d.severity == "error"]
        if refused:  # a pin the .ld cannot hold: no file LDmicro would refuse
            raise UserError("; ".join(refused))
        try:
            data = encode_text(text.replace("\n", "\r\n"), ls.settings.encoding)
        except UnicodeEncodeError as problem:
            raise UserError(f"{problem.object[problem.start]!r} cannot be written in {ls.settings.encoding}, "
                            "the code page of the .ld file; rename it or choose another ladder.encoding") from None
        if long_lines:
            ls.window_show_message(types.ShowMessageParams(
                type=types.MessageType.Warning, message="; ".join(d.message for d in long_lines)))
    else:
        from lang.textform.writer import render_program

        out = source.with_suffix(".ladder")
        data = encode_text(render_program(program), "utf-8")
    if out == source:
        raise UserError(f"{source.name} is already a {'.ld' if target == 'ld' else '.ladder'} file")
    try:
        write_whole(out, data)
    except OSError as problem:
        raise UserError(f"cannot write {out}: {problem.strerror or problem}") from problem
    return {"path": str(out)}


def register(server) -> None:
    @server.on_command("ladder.convert")
    def convert_command(ls, *args):
        uri = _uri_argument(args)
        target = args[1] if len(args) > 1 else None
        if isinstance(target, dict):  # {"target": "ld"} is accepted too
            target = target.get("target")
        return convert(ls, uri, target)

    @server.on_command("ladder.build")
    def build_command(ls, *args):
        return build(ls, _uri_argument(args))

    def saved(ls, uri):
        if not ls.settings.compile_on_save:
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


def build(ls, uri: str) -> dict:
    """Compile the document's program to a HEX file beside it (`ladder build`)."""
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
