"""Open documents and their analysis (ide.analysis, with the document's URI,
version and position conversion): which language a document is, its
program, the reader's and the checks' diagnostics, and the lazily built
helpers the features share (locator, name index, position conversion).

An analysis belongs to one exact text: features ask `Documents.analysis(uri)`,
which re-reads only when the text changed since the last request. The text
reader caches rungs by their lines, so after a one-character edit only the
touched rung is read again (`ide.incremental` keeps the rest of the program),
and each document's `Checker` checks again only what the edit can change
(`lang.checks.incremental`); its symbol table serves the features too.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from functools import cached_property
from pathlib import Path, PurePath, PureWindowsPath
from typing import TYPE_CHECKING, Any, TypeVar, overload

from lsprotocol import types
from pygls import uris

import ide.analysis
from ide.analysis import RungResults, moved_since, still_moved
from ide.incremental import IncrementalReader
from lang import config
from lang.checks import Checker
from lang.config import NONE, Severities
from lang.diagnostics import WARNING, Diagnostic
from lang.model import Program, Rung, Span

from .positions import Positions
from .text import LineDocument

if TYPE_CHECKING:
    from pygls.workspace import PositionCodec, TextDocument

    from .server import LadderServer

log = logging.getLogger(__name__)

LADDER = "ladder"  # the text form: .ladder, LDmicro export .txt
LD = "ld"  # LDmicro .ld files
LANGUAGE_IDS = {"ladder": LADDER, "ldmicro": LD}
# LDmicro loads 9,999 rungs (about 3 MB drawn); this leaves room for programs
# twice as long (the benchmark's 18,000 rungs are 5.1 MB). A bigger document is
# not analysed, so that the server stays responsive whatever it is sent
MAX_CHARS = 8_000_000
TOO_LARGE = "lsp-too-large"


P = TypeVar("P", bound=PurePath)


@overload
def file_path(uri: str) -> Path | None: ...


@overload
def file_path(uri: str, flavour: type[P]) -> P | None: ...


def file_path(uri: str, flavour: type[PurePath] = Path) -> PurePath | None:
    """The file a `file:` URI names, None for another scheme or a URI that
    names no file. pygls reads the URI as VS Code writes it: percent-escapes,
    a drive letter (`file:///c%3A/Users/me/prog.ladder`, `file:///C:/...`),
    a UNC share (`file://server/share/prog.ladder`) as `//server/share/...`.
    The flavour (the machine's own `Path`; `PureWindowsPath` reads a URI as a
    Windows server does) decides what a backslash is and what is absolute: a
    path that is not (a drive letter on Linux) is None, so that nothing is
    ever written relative to the server's working folder."""
    found = uris.to_fs_path(uri)
    path = flavour(found) if found else None
    return path if path is not None and path.name and path.is_absolute() else None


def language_of(uri: str, text: str, language_id: str | None = None) -> str | None:
    """docs/lsp-protocol.md: `*.ladder`, `*.txt` starting `LDmicro export
    text`, `*.ld` starting `LDmicro`; other documents only when the client says
    they are ours (an untitled buffer)."""
    # any scheme (an untitled buffer may have a name); a backslash separates as `/` does, as on Windows
    suffix = PureWindowsPath(uris.urlparse(uri)[2]).suffix.lower()
    head = text[:64].lstrip("\ufeff")
    if suffix == ".ladder":
        return LADDER
    if suffix == ".txt":
        return LADDER if head.startswith("LDmicro export text") else None
    if suffix == ".ld":
        return LD if head.startswith("LDmicro") else None
    return LANGUAGE_IDS.get(language_id or "")


class Analysis(ide.analysis.Analysis):
    """One version of one open document: its analysis, its URI and version,
    and positions in the client's encoding."""

    def __init__(self, uri: str, version: int | None, kind: str, text: str, program: Program,
                 problems: list[Diagnostic], codec: PositionCodec | None, checker: Checker | None = None,
                 moved: dict[int, tuple[Rung, int]] | None = None):
        super().__init__(kind, text, program, problems, checker, moved)
        self.uri = uri
        self.version = version
        self._codec = codec

    @cached_property
    def positions(self) -> Positions:
        return Positions(self.lines, self._codec, self.text.isascii())


class Documents:
    def __init__(self, server: LadderServer):
        self.server = server
        self._analyses: dict[str, Analysis] = {}
        self._readers: dict[str, IncrementalReader] = {}
        self._checkers: dict[str, Checker] = {}
        self._results: dict[str, RungResults] = {}
        # feature -> fn(value, lines moved): how a per-rung result follows its rung
        self.shifters: dict[str, Callable[[Any, int], Any]] = {}
        self._config_errors: set[str] = set()

    def _document(self, uri: str) -> TextDocument | None:
        try:
            return self.server.workspace.get_text_document(uri)
        except Exception:  # no workspace yet, or a bad URI
            return None

    def text(self, uri: str) -> str | None:
        document = self._document(uri)
        if document is None:
            return None
        try:
            return document.source
        except (OSError, UnicodeDecodeError, ValueError):
            return None

    def language(self, uri: str) -> str | None:
        document = self._document(uri)
        text = self.text(uri)
        if document is None or text is None:
            return None
        return language_of(uri, text, getattr(document, "language_id", None))

    def analysis(self, uri: str, include_too_large: bool = False) -> Analysis | None:
        """The analysis of the document's current text (None: not ours, or
        too large to analyse unless `include_too_large`: diagnostics say so)."""
        found = self._analysis(uri)
        if found is not None and found.too_large and not include_too_large:
            return None
        return found

    def latest(self, uri: str) -> Analysis | None:
        """The analysis made last, whether or not the text changed since
        (None once the document is closed): no reading."""
        return self._analyses.get(uri)

    def _analysis(self, uri: str) -> Analysis | None:
        document = self._document(uri)
        if document is None:
            return None
        text = self.text(uri)
        if text is None:
            return None
        cached = self._analyses.get(uri)
        if cached is not None and (cached.text is text or cached.text == text):
            cached.text = text
            cached.version = document.version  # an edit that changed nothing still has a new version
            return cached
        # the lines untouched since the text was read last (every read takes them)
        edited = document.take_edited() if isinstance(document, LineDocument) else None
        kind = language_of(uri, text, getattr(document, "language_id", None))
        if kind is None:
            self._analyses.pop(uri, None)
            return None
        if len(text) > MAX_CHARS:
            self._readers.pop(uri, None)
            self._checkers.pop(uri, None)
            problem = Diagnostic(TOO_LARGE, WARNING, f"this file is too large for the language server "
                                 f"({len(text) / 1e6:.1f} MB; it reads files up to {MAX_CHARS / 1e6:g} MB): "
                                 "not analysed", Span.at(0, 0))
            analysis = Analysis(uri, document.version, kind, text, Program(), [problem],
                                self.server.workspace.position_codec)
            analysis.too_large = True
            self._analyses[uri] = analysis
            return analysis
        reader = self._readers.get(uri)
        if reader is None or reader.kind != kind:
            reader = self._readers[uri] = IncrementalReader(kind)
            self._checkers[uri] = Checker()
        program, problems = reader.read(text, edited)
        moved = reader.moved
        if cached is not None and not cached.checked and cached.moved is not moved:
            moved = moved_since(cached.moved, program, moved, cached.program)  # the version before was read, not checked
        analysis = Analysis(uri, document.version, kind, text, program, problems,
                            self.server.workspace.position_codec, self._checkers[uri], moved)
        analysis.severities = self.severities(uri)
        analysis.split = reader.split()
        analysis.memo = self._results.setdefault(uri, RungResults(self.shifters))
        if cached is not None:
            analysis.moved_from = still_moved(cached.moved_from, program, reader.moved, cached.program)
        analysis.memo.prune(program, analysis.moved_from)
        if cached is not None and cached.kind == kind:
            analysis.follow(cached, reader.moved)
        self._analyses[uri] = analysis
        return analysis

    def reconfigure(self) -> None:
        """Settings changed: every kept analysis checks again with the new severities."""
        self._config_errors.clear()
        for uri, analysis in self._analyses.items():
            analysis.severities = self.severities(uri)
            analysis.__dict__.pop("checks", None)

    def severities(self, uri: str) -> Severities:
        """The settings file's choices for the document's folder, with the
        editor's `ladder.diagnostics` on top; a file that cannot be used is
        reported in the log once and left out."""
        path = file_path(uri)
        try:
            found = config.find(path) if path is not None else NONE
        except config.ConfigError as bad:
            if str(bad) not in self._config_errors:
                self._config_errors.add(str(bad))
                self.server.log(f"ladder: {bad}", types.MessageType.Warning)
            found = NONE
        return found.merged(self.server.settings.severities)

    def forget(self, uri: str) -> None:
        self._analyses.pop(uri, None)
        self._results.pop(uri, None)
        self._readers.pop(uri, None)
        self._checkers.pop(uri, None)

    def uris(self) -> list[str]:
        return list(self._analyses)
