"""Located problems, as every reader, check and back end reports them."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from .codes import CODES
from .model import Span

ERROR = "error"
WARNING = "warning"
INFO = "info"  # a fact worth knowing that is often intended (LD133): the editor shows it faintly


@dataclass(frozen=True)
class Related:
    span: Span
    message: str


@dataclass(frozen=True)
class Rename:
    """Rename a name everywhere it is used (drawing, I/O, VAR LIST, DETAILS)."""

    old: str
    new: str


@dataclass(frozen=True)
class SetPart:
    """Select another part (the MICRO setting)."""

    name: str


@dataclass(frozen=True)
class Replace:
    """Replace the text of a one-line span (a glyph moved into its column)."""

    span: Span
    text: str

    def shifted(self, lines: int) -> Replace:
        return Replace(self.span.shifted(lines), self.text)


@dataclass(frozen=True)
class Fix:
    """A change that removes the diagnostic; the editor offers it as a quick
    fix and `ladder check --fix` applies a diagnostic's first one."""

    title: str
    change: Rename | SetPart | Replace


@dataclass(frozen=True)
class Diagnostic:
    code: str  # stable code, e.g. "LD101"; documented by `ladder explain CODE`
    severity: str  # ERROR, WARNING or INFO
    message: str
    span: Span | None
    related: tuple[Related, ...] = field(default=())
    fixes: tuple[Fix, ...] = field(default=(), compare=False)

    def shifted(self, lines: int) -> Diagnostic:
        """The diagnostic with every place moved `lines` lines down (up when negative)."""
        return replace(self, span=self.span.shifted(lines) if self.span is not None else None,
                       related=tuple(Related(r.span.shifted(lines), r.message) for r in self.related),
                       fixes=tuple(Fix(f.title, f.change.shifted(lines)) if isinstance(f.change, Replace) else f
                                   for f in self.fixes))

    def format(self, path: str) -> str:
        """`path:line:col: severity CODE message`, 1-based line and column."""
        line, col = (self.span.line + 1, self.span.col + 1) if self.span else (1, 1)
        return f"{path}:{line}:{col}: {self.severity} {self.code} {self.message}"


def error(code: str, message: str, span: Span | None, *related: Related) -> Diagnostic:
    return Diagnostic(code, ERROR, message, span, tuple(related))


def warning(code: str, message: str, span: Span | None, *related: Related) -> Diagnostic:
    return Diagnostic(code, WARNING, message, span, tuple(related))


def report(code: str, message: str, span: Span | None, *related: Related, severity: str | None = None,
           fixes: tuple[Fix, ...] = ()) -> Diagnostic:
    """A diagnostic at its code's default severity (the registry's), or at
    `severity` where the context decides (LD501 is an error when building)."""
    return Diagnostic(code, severity or CODES[code].severity, message, span, tuple(related), fixes)
