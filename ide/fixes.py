"""The fixes diagnostics carry, as edits of the source text: the language
server offers them as quick fixes, `ladder check --fix` applies them."""

from __future__ import annotations

from lang.checks import check_program
from lang.config import NONE, Severities
from lang.diagnostics import ERROR, Diagnostic, Fix, Rename, Replace, SetPart
from lang.loader import parse
from lang.model import Program

from .document import newline
from .edits import EditError, LineEdit, TextEdit, rename
from .locate import Locator

_ROUNDS = 200  # each round removes one diagnostic; a program has far fewer fixable ones


def fix_edits(fix: Fix, program: Program, text: str, kind: str) -> tuple[list[LineEdit], list[TextEdit]]:
    """The line and column edits that make `fix` (EditError when it cannot be made)."""
    if isinstance(fix.change, Rename):
        locator = Locator(program, text.splitlines(), kind)
        return rename(program, locator, text, fix.change.old, fix.change.new, kind)
    if isinstance(fix.change, Replace):
        place = fix.change.span
        return [], [TextEdit(place.line, place.col, place.end_col, fix.change.text)]
    assert isinstance(fix.change, SetPart)
    span = program.settings.mcu_span
    if span is None:
        return [], []
    return [], [TextEdit(span.line, span.col, span.end_col, fix.change.name)]


def apply_edits(text: str, line_edits: list[LineEdit], text_edits: list[TextEdit]) -> str:
    """The text with the edits made (they do not overlap; line endings kept)."""
    nl = newline(text)
    lines = text.splitlines()
    for edit in sorted(text_edits, key=lambda e: (e.line, e.col), reverse=True):
        line = lines[edit.line]
        lines[edit.line] = line[:edit.col] + edit.text + line[edit.end_col:]
    for line_edit in sorted(line_edits, key=lambda e: e.first, reverse=True):
        lines[line_edit.first:line_edit.last] = list(line_edit.lines)
    return nl.join(lines) + (nl if text.endswith(("\n", "\r")) else "")


def fix_all(text: str, kind: str, severities: Severities = NONE) -> tuple[str, list[str]]:
    """The text with every diagnostic that has exactly one fix fixed, one at
    a time (each fix changes what the next one sees), and the fixes' titles.
    Where a diagnostic offers a choice (a coil named `count`: `Ycount`,
    `Rcount` or `Mcount`?) the user chooses, in the editor. The reader's
    own fixes (a connector glyph moved into its column) come first; the
    checks' are made only once the text reads without error, as a rename
    must see every use of the name."""
    applied: list[str] = []
    for _ in range(_ROUNDS):
        program, problems = parse(text, kind)
        if any(p.severity == ERROR for p in problems):
            made = _first_fix(text, kind, program, problems)
        else:
            made = _first_fix(text, kind, program, check_program(program, severities=severities))
        if made is None:
            break
        text, title = made
        applied.append(title)
    return text, applied


def _first_fix(text: str, kind: str, program: Program, diagnostics: list[Diagnostic]) -> tuple[str, str] | None:
    for diagnostic in diagnostics:
        if len(diagnostic.fixes) != 1:
            continue
        fix = diagnostic.fixes[0]
        try:
            changed = apply_edits(text, *fix_edits(fix, program, text, kind))
        except EditError:
            continue
        if changed != text:
            return changed, fix.title
    return None
