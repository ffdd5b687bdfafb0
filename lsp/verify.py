"""`ladder verify` in the editor (docs/lsp-protocol.md, "Verification"): code
lenses on the PROPERTIES section (ide.verify), the `ladder.verify` command
that proves the properties of the document's current version and publishes
each result as a diagnostic on its property's line, and `ladder.verify.step`
(a lens, and a code action on the diagnostic) that starts the document's
simulation replaying the counterexample, to step through scan by scan.

The prover runs on a thread of its own, so that the server keeps answering
while it works (z3 leaves Python's lock while it solves). One thread: z3's
Python API shares one context, which two threads must not use at once, so a
second document's verification waits for the first.

Results belong to the version they were proved on: any edit of the document
drops them (their diagnostics go with the next publication, and the lenses
say "Verify" again), and a verification that an edit overtook is not shown
(one message says to verify again). Without z3, one message names the pip
command, as `ladder verify` does."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from lsprotocol import types

from ide import verify as ide_verify
from ide.verify import LensKind, Severity, Verification, VerifyError
from lang.verify import DEFAULT_BOUND, DEFAULT_TIMEOUT_S

from .documents import Analysis
from .protocol import UserError

if TYPE_CHECKING:
    from .server import LadderServer

VERIFY = "ladder.verify"
STEP = "ladder.verify.step"
SOURCE = "ladder verify"
SEVERITIES = {Severity.INFORMATION: types.DiagnosticSeverity.Information,
              Severity.WARNING: types.DiagnosticSeverity.Warning, Severity.ERROR: types.DiagnosticSeverity.Error}

Json = dict[str, Any]


@dataclass
class Proved:
    """A document's last verification and the version it was proved on."""

    analysis: Analysis
    verification: Verification


class Verifications:
    def __init__(self, server: LadderServer):
        self.server = server
        self.proved: dict[str, Proved] = {}
        self.running: set[str] = set()
        self.executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="ladder-verify")

    # --- running the prover ---------------------------------------------------------

    async def verify(self, uri: str, line: int | None, bound: int, timeout_s: float) -> Json:
        analysis = self.server.documents.analysis(uri)
        if analysis is None:
            raise UserError("this document is not a ladder program")
        if uri in self.running:
            raise UserError("this document is being verified already")
        try:
            properties = ide_verify.ready(analysis, line)
        except VerifyError as problem:
            return self._refused(uri, str(problem))
        revision = self.server.revision(uri)
        self.running.add(uri)
        self._refresh_lenses()
        try:
            loop = asyncio.get_running_loop()
            verification = await loop.run_in_executor(
                self.executor, ide_verify.run, analysis.program, properties, bound, timeout_s, line)
        except VerifyError as problem:
            return self._refused(uri, str(problem))
        finally:
            self.running.discard(uri)
            self._refresh_lenses()
        if self.server.revision(uri) != revision:
            return self._refused(uri, "the document changed while it was verified: verify it again",
                                 types.MessageType.Warning)
        before = self.proved.get(uri)
        if before is not None and before.analysis.version != analysis.version:
            before = None
        self.proved[uri] = Proved(analysis, ide_verify.merged(before.verification if before else None, verification))
        if self.server.diagnostics is not None:
            self.server.diagnostics.publish(uri)
        self._refresh_lenses()
        return {"uri": uri, "version": analysis.version, "results": [
            {"line": f.span.line, "severity": f.severity.value, "message": f.message, "steppable": f.steppable}
            for f in ide_verify.findings(analysis, verification)]}

    def _refused(self, uri: str, message: str, kind: types.MessageType = types.MessageType.Error) -> Json:
        """Nothing verified: one message to the user, and the same as the answer."""
        self.server.window_show_message(types.ShowMessageParams(type=kind, message=f"ladder verify: {message}"))
        return {"uri": uri, "error": message}

    def _refresh_lenses(self) -> None:
        if self.server.client_supports("workspace", "code_lens", "refresh_support"):
            try:
                future = self.server.protocol.send_request(types.WORKSPACE_CODE_LENS_REFRESH, None)
                future.add_done_callback(lambda f: f.cancelled() or f.exception())  # nothing depends on it
            except Exception:
                pass

    def forget(self, uri: str) -> None:
        self.proved.pop(uri, None)

    # --- what the editor shows ---------------------------------------------------------

    def current(self, uri: str) -> Verification | None:
        proved = self.proved.get(uri)
        return proved.verification if proved is not None else None

    def diagnostics(self, analysis: Analysis) -> list[types.Diagnostic]:
        proved = self.proved.get(analysis.uri)
        if proved is None or proved.analysis.version != analysis.version:
            return []
        positions = proved.analysis.positions
        related = self.server.client_supports("text_document", "publish_diagnostics", "related_information")
        return [types.Diagnostic(
            range=positions.range(f.span), message=f.message, severity=SEVERITIES[f.severity], source=SOURCE,
            related_information=[types.DiagnosticRelatedInformation(
                location=types.Location(uri=analysis.uri, range=positions.range(r.span)), message=r.message)
                for r in f.related] if related and f.related else None)
            for f in ide_verify.findings(proved.analysis, proved.verification)]

    def lenses(self, analysis: Analysis) -> list[types.CodeLens]:
        found = []
        for lens in ide_verify.lenses(analysis, self.current(analysis.uri), analysis.uri in self.running):
            arguments: list[object] = [analysis.uri] + ([{"line": lens.property_line}] if lens.property_line is not None
                                                        else [])
            command = VERIFY if lens.kind is LensKind.VERIFY else STEP
            start = analysis.positions.to_client(lens.line, 0)
            found.append(types.CodeLens(range=types.Range(start=start, end=start),
                                        command=types.Command(title=lens.title, command=command, arguments=arguments)))
        return found

    def actions(self, analysis: Analysis, params: types.CodeActionParams) -> list[types.CodeAction]:
        """"Step through the counterexample" on a property line that has one."""
        verification = self.current(analysis.uri)
        if verification is None:
            return []
        found = []
        for line in range(params.range.start.line, params.range.end.line + 1):
            outcome = verification.at(line)
            if outcome is None or not outcome.scenario:
                continue
            title = f"Step through the {ide_verify.sequence_kind(outcome.prop)}"
            ours = [d for d in params.context.diagnostics if d.source == SOURCE and d.range.start.line == line]
            found.append(types.CodeAction(title=title, kind=types.CodeActionKind.QuickFix, diagnostics=ours or None,
                                          command=types.Command(title=title, command=STEP,
                                                                arguments=[analysis.uri, {"line": line}])))
        return found

    # --- the counterexample as a simulation ---------------------------------------------

    def step(self, uri: str, line: int) -> Json:
        verification = self.current(uri)
        if verification is None:
            raise UserError("this document has no verification: verify it first")
        try:
            replay = ide_verify.replay(verification, line)
        except VerifyError as problem:
            raise UserError(str(problem)) from problem
        assert self.server.simulations is not None
        state = self.server.simulations.start(uri, replay)
        witness = verification.at(line)
        assert witness is not None and witness.result.witness is not None
        scan = witness.result.witness.scan + 1
        self.server.window_show_message(types.ShowMessageParams(
            type=types.MessageType.Info,
            message=f"Simulating the {replay.name}: scan {scan} ({replay.end_us / 1000:g} ms) decides it; "
                    f"step to it scan by scan."))
        return state


def _options(args: Sequence[object]) -> Json:
    """The arguments after the URI: `{"line": 57, "bound": 50, "timeoutS": 60}`, each optional."""
    if len(args) < 2:
        return {}
    if not isinstance(args[1], dict):
        raise UserError("the second argument must be an object such as {\"line\": 57}")
    return args[1]


def _whole(value: object, what: str, default: int | None) -> int | None:
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, int):
        raise UserError(f"{what} must be a whole number, not {json.dumps(value)}")
    return value


def register(server: LadderServer) -> None:
    verifications = server.verifications = Verifications(server)
    if server.diagnostics is not None:
        server.diagnostics.sources.append(verifications.diagnostics)

    def uri_of(args: Sequence[object]) -> str:
        if not args or not isinstance(args[0], str):
            raise UserError("the first argument must be the document's URI")
        return args[0]

    @server.on(types.TEXT_DOCUMENT_CODE_LENS, types.CodeLensOptions(resolve_provider=False))
    def code_lens(ls: LadderServer, params: types.CodeLensParams) -> list[types.CodeLens]:
        analysis = ls.documents.analysis(params.text_document.uri)
        return verifications.lenses(analysis) if analysis is not None else []

    @server.on_command(VERIFY)
    async def verify(ls: LadderServer, *args: object) -> Json:
        uri, options = uri_of(args), _options(args)
        line = _whole(options.get("line"), "line", None)
        bound = _whole(options.get("bound"), "bound", DEFAULT_BOUND)
        timeout = options.get("timeoutS", DEFAULT_TIMEOUT_S)
        if bound is None or bound < 1 or isinstance(timeout, bool) or not isinstance(timeout, (int, float)) \
                or timeout <= 0:
            raise UserError("bound must be at least 1 and timeoutS a positive number of seconds")
        return await verifications.verify(uri, line, bound, float(timeout))

    @server.on_command(STEP)
    def step(ls: LadderServer, *args: object) -> Json:
        uri, options = uri_of(args), _options(args)
        line = _whole(options.get("line"), "line", None)
        if line is None:
            raise UserError("line is missing: the line of the property whose counterexample to step through")
        return verifications.step(uri, line)

    def changed(ls: LadderServer, uri: str | None) -> None:
        if uri is not None:
            verifications.forget(uri)

    server.subscribe("changed", changed)
    server.subscribe("closed", changed)
