"""Code actions as LSP's: the quick fixes and structural edits of
ide.actions, each as a workspace edit, and the conversion between `.ladder`
and `.ld` (the `ladder.convert` command)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from lsprotocol import types

from ide import actions as ide_actions
from ide.actions import Action

from .documents import LADDER, Analysis
from .navigation import workspace_edit

if TYPE_CHECKING:
    from .server import LadderServer

QUICKFIX = "quickfix"
REWRITE = "refactor.rewrite"
INSERT = "refactor.insert"  # our own sub-kind of refactor
SOURCE = "source"
KINDS = {ide_actions.Kind.QUICKFIX: QUICKFIX, ide_actions.Kind.REWRITE: REWRITE, ide_actions.Kind.INSERT: INSERT}


def register(server: LadderServer) -> None:
    @server.on(types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(
        code_action_kinds=[QUICKFIX, REWRITE, INSERT, SOURCE]))
    def code_action(ls: LadderServer, params: types.CodeActionParams) -> list[types.CodeAction] | None:
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        wanted = params.context.only
        found: list[types.CodeAction] = []
        if _wants(wanted, QUICKFIX):
            found += quick_fixes(ls, analysis, params.context.diagnostics)
            if ls.verifications is not None:
                found += ls.verifications.actions(analysis, params)
        if _wants(wanted, REWRITE) or _wants(wanted, INSERT):
            start = analysis.positions.from_client(params.range.start)
            end = analysis.positions.from_client(params.range.end)
            found += [_action(ls, analysis, a) for a in ide_actions.structural(analysis, start, end)]
        if _wants(wanted, SOURCE):
            found += conversions(analysis)
        return found


def _kind(value: types.CodeActionKind | str) -> str:
    return value.value if isinstance(value, types.CodeActionKind) else value


def _wants(only: Sequence[types.CodeActionKind | str] | None, kind: str) -> bool:
    """LSP: `only` lists kinds or their parents ("refactor" asks for "refactor.rewrite")."""
    if not only:
        return True
    return any(kind == _kind(k) or kind.startswith(_kind(k) + ".") for k in only)


def _action(ls: LadderServer, analysis: Analysis, action: Action,
            diagnostics: list[types.Diagnostic] | None = None) -> types.CodeAction:
    return types.CodeAction(title=action.title, kind=KINDS[action.kind], diagnostics=diagnostics,
                            edit=workspace_edit(ls, analysis, action.line_edits, action.text_edits),
                            is_preferred=action.preferred if action.kind is ide_actions.Kind.QUICKFIX else None)


def quick_fixes(ls: LadderServer, analysis: Analysis, diagnostics: Sequence[types.Diagnostic] | None
                ) -> list[types.CodeAction]:
    """The fixes of our diagnostics among the client's (the same code at the same place)."""
    found = []
    offered = ide_actions.offered(analysis)
    for diagnostic in diagnostics or ():
        if diagnostic.source not in (None, "ladder"):
            continue
        for ours in offered:
            if ours.code != diagnostic.code or ours.span is None or \
                    analysis.positions.range(ours.span) != diagnostic.range:
                continue
            found += [_action(ls, analysis, a, [diagnostic]) for a in ide_actions.quick_fixes(analysis, ours)]
    return found


def conversions(analysis: Analysis) -> list[types.CodeAction]:
    target = "ld" if analysis.kind == LADDER else "ladder"
    if analysis.has_errors:
        return []
    title = "Convert to an LDmicro .ld file" if target == "ld" else "Convert to a .ladder text file"
    command = types.Command(title=title, command="ladder.convert", arguments=[analysis.uri, target])
    return [types.CodeAction(title=title, kind=SOURCE, command=command)]
