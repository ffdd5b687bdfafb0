"""What the editor features read of a document: one version of its text,
read and checked. The language server's analysis of a document
(`lsp.documents.Analysis`) is one; the features take it as it is, so that a
request copies nothing of a big document."""

from __future__ import annotations

from typing import Protocol

from lang.diagnostics import Diagnostic
from lang.index import ProgramIndex
from lang.model import Program

from .locate import Locator


class Document(Protocol):
    @property
    def kind(self) -> str:
        """`lang.loader.TEXT_KIND` or `LD_KIND`."""

    @property
    def text(self) -> str: ...

    @property
    def lines(self) -> list[str]: ...

    @property
    def program(self) -> Program: ...

    @property
    def problems(self) -> list[Diagnostic]:
        """The reader's."""

    @property
    def checks(self) -> list[Diagnostic]:
        """The checks', as `ladder check` gives them."""

    @property
    def has_errors(self) -> bool:
        """The reader found errors."""

    @property
    def index(self) -> ProgramIndex: ...

    @property
    def locator(self) -> Locator: ...

    def line(self, number: int) -> str:
        """The line, "" past the end."""


def newline(text: str) -> str:
    """The line ending a text uses (its first lines')."""
    return "\r\n" if "\r\n" in text[:4096] else "\n"
