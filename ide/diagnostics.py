"""The diagnostics an editor shows for a document: the reader's and the
checks', and those of its last build until it changes."""

from __future__ import annotations

from lang.diagnostics import Diagnostic


def shown(checked: list[Diagnostic], compiled: list[Diagnostic]) -> list[Diagnostic]:
    """The document's diagnostics and the last build's; where the build
    reports what the checks do (LD501: a warning while editing, an error
    when compiling), only the build's."""
    replaced = {(d.code, d.span) for d in compiled}
    return [d for d in checked if (d.code, d.span) not in replaced] + compiled
