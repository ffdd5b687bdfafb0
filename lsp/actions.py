"""Code actions: quick fixes for the checks (a name with a prefix its
instruction does not allow is renamed to each allowed prefix, e.g. `Xlamp`
written by a coil -> `Ylamp` or `Rlamp`; a misspelt part), structural edits
of the drawing (insert, delete, move an element, a parallel branch around
the selection, a new rung; each rung is drawn again, ide.edits) and the
conversion between `.ladder` and `.ld` (the `ladder.convert` command)."""

from __future__ import annotations

from lsprotocol import types

from ide import edits
from ide.fixes import fix_edits
from lang.textform.rungs import UnreadRung

from .documents import LADDER
from .navigation import workspace_edit

QUICKFIX = "quickfix"
REWRITE = "refactor.rewrite"
INSERT = "refactor.insert"  # our own sub-kind of refactor
SOURCE = "source"
INSERT_KINDS = ("CONTACTS", "COIL", "TON", "OSR", "CTU", "MOVE")


def register(server) -> None:
    @server.on(types.TEXT_DOCUMENT_CODE_ACTION, types.CodeActionOptions(
        code_action_kinds=[QUICKFIX, REWRITE, INSERT, SOURCE]))
    def code_action(ls, params: types.CodeActionParams):
        analysis = ls.documents.analysis(params.text_document.uri)
        if analysis is None:
            return None
        wanted = params.context.only
        actions: list[types.CodeAction] = []
        if _wants(wanted, QUICKFIX):
            actions += quick_fixes(ls, analysis, params.context.diagnostics)
        if _wants(wanted, REWRITE) or _wants(wanted, INSERT):
            actions += structural(ls, analysis, params.range)
        if _wants(wanted, SOURCE):
            actions += conversions(analysis)
        return actions


def _kind(value) -> str:
    return str(getattr(value, "value", value))


def _wants(only, kind: str) -> bool:
    """LSP: `only` lists kinds or their parents ("refactor" asks for "refactor.rewrite")."""
    if not only:
        return True
    return any(kind == _kind(k) or kind.startswith(_kind(k) + ".") for k in only)


def _action(title: str, kind, edit: types.WorkspaceEdit | None = None, command=None, diagnostics=None,
            preferred: bool | None = None) -> types.CodeAction:
    return types.CodeAction(title=title, kind=kind, edit=edit, command=command, diagnostics=diagnostics,
                            is_preferred=preferred)


# --- quick fixes ------------------------------------------------------------------------------

def quick_fixes(ls, analysis, diagnostics) -> list[types.CodeAction]:
    """The fixes the reader or the checks attached to the client's
    diagnostics (ide.fixes turns each into edits, as `ladder check --fix`
    does): the reader's while the text has reading errors (a rename must see
    every use of a name), else the checks'."""
    actions = []
    offered = analysis.problems if analysis.has_errors else analysis.checks
    for diagnostic in diagnostics or ():
        if diagnostic.source not in (None, "ladder"):
            continue
        for found in offered:
            if found.code != diagnostic.code or found.span is None or \
                    analysis.positions.range(found.span) != diagnostic.range:
                continue
            for position, fix in enumerate(found.fixes):
                try:
                    change = workspace_edit(ls, analysis, *fix_edits(fix, analysis.program, analysis.text,
                                                                       analysis.kind))
                except edits.EditError:
                    continue
                actions.append(_action(fix.title, QUICKFIX, change, diagnostics=[diagnostic],
                                       preferred=position == 0))
    return actions


# --- structural edits ----------------------------------------------------------------------------

def selected_elements(analysis, selection: types.Range) -> tuple[int | None, list]:
    """The rung under the selection and its elements whose glyph the
    selection touches (or the element under the cursor)."""
    locator = analysis.locator
    start = analysis.positions.from_client(selection.start)
    end = analysis.positions.from_client(selection.end)
    rung_index = locator.rung_at(start[0])
    if rung_index is None:
        rung_index = locator.rung_at(end[0])
    if rung_index is None:
        return None, []
    rung = analysis.program.rungs[rung_index]
    if start == end:
        hit = locator.hit(start[0], start[1])
        return rung_index, [hit.element] if hit is not None and hit.element is not None else []
    chosen = []
    for element in rung.elements():
        span = element.span
        glyph = locator.glyph_span(element) if analysis.kind == LADDER else span
        if span is None:
            continue
        rows = range(span.line, span.end_line + 1)
        inside_rows = any(start[0] <= r <= end[0] for r in rows)
        if not inside_rows:
            continue
        if start[0] == end[0] and (glyph.end_col <= start[1] or glyph.col >= end[1]):
            continue
        chosen.append(element)
    return rung_index, chosen


def structural(ls, analysis, selection: types.Range) -> list[types.CodeAction]:
    if analysis.kind != LADDER:
        return []
    rung_index, chosen = selected_elements(analysis, selection)
    if rung_index is None:
        return []
    rung = analysis.program.rungs[rung_index]
    if isinstance(rung, UnreadRung):
        return []  # redrawn from what could be read, it would lose what could not
    actions: list[types.CodeAction] = []

    def offer(title: str, kind, make) -> None:
        try:
            new = make()
            if isinstance(new, edits.LineEdit):
                change = workspace_edit(ls, analysis, [new], [])
            else:
                change = workspace_edit(ls, analysis, [edits.redraw(analysis.locator, analysis.text, rung_index,
                                                                     new)], [])
        except edits.EditError:
            return
        actions.append(_action(title, kind, change))

    locator, text = analysis.locator, analysis.text
    if not rung.is_comment and len(chosen) == 1:
        element = chosen[0]
        what = _describe(element)
        offer(f"Delete {what}", REWRITE, lambda: edits.delete_element(rung, element))
        offer(f"Move {what} left", REWRITE, lambda: edits.move_element(rung, element, -1))
        offer(f"Move {what} right", REWRITE, lambda: edits.move_element(rung, element, +1))
        for kind in INSERT_KINDS:
            word = _word(kind)
            offer(f"Insert {word} before {what}", INSERT,
                  lambda kind=kind: edits.insert_element(rung, element, edits.new_element(kind), after=False))
            offer(f"Insert {word} after {what}", INSERT,
                  lambda kind=kind: edits.insert_element(rung, element, edits.new_element(kind), after=True))
    if not rung.is_comment and chosen:
        around = _describe(chosen[0]) if len(chosen) == 1 else f"{len(chosen)} elements"
        offer(f"Add a parallel branch (contact) around {around}", INSERT,
              lambda: edits.add_parallel(rung, chosen, edits.new_element("CONTACTS")))
        if all(e.spec.eol for e in chosen):
            offer(f"Add a parallel coil beside {around}", INSERT,
                  lambda: edits.add_parallel(rung, chosen, edits.new_element("COIL")))
    offer("Insert a rung above", INSERT, lambda: edits.insert_rung(locator, text, rung_index, edits.new_rung()))
    offer("Insert a rung below", INSERT, lambda: edits.insert_rung(locator, text, rung_index + 1, edits.new_rung()))
    offer("Insert a comment rung above", INSERT,
          lambda: edits.insert_rung(locator, text, rung_index, edits.comment_rung("comment")))
    return actions


def _word(kind: str) -> str:
    return {"CONTACTS": "contact", "COIL": "coil"}.get(kind, kind)


def _describe(element) -> str:
    from lang.labels import describe

    return describe(element)


# --- conversion ------------------------------------------------------------------------------

def conversions(analysis) -> list[types.CodeAction]:
    target = "ld" if analysis.kind == LADDER else "ladder"
    if analysis.has_errors:
        return []
    title = "Convert to an LDmicro .ld file" if target == "ld" else "Convert to a .ladder text file"
    command = types.Command(title=title, command="ladder.convert", arguments=[analysis.uri, target])
    return [_action(title, SOURCE, command=command)]
