"""Open documents and their analysis: which language a document is, its
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
from typing import TYPE_CHECKING, Any, TypeVar, cast, overload

from lsprotocol import types
from pygls import uris

from ide.incremental import IncrementalReader
from ide.locate import Locator
from lang import codes, config
from lang.checks import Checker
from lang.config import NONE, Severities
from lang.diagnostics import ERROR, WARNING, Diagnostic
from lang.index import ProgramIndex
from lang.loader import checkable, checked
from lang.model import Program, Rung, Span

from .positions import Positions

if TYPE_CHECKING:
    from pygls.workspace import PositionCodec, TextDocument

    from .server import LadderServer

log = logging.getLogger(__name__)

LADDER = "ladder"  # the text form: .ladder, LDmicro export .txt
LD = "ld"  # LDmicro .ld files
LANGUAGE_IDS = {"ladder": LADDER, "ldmicro": LD}
# LDmicro programs are far below this (999 rungs at most); a bigger document is
# not analysed, so that the server stays responsive whatever it is sent
MAX_CHARS = 5_000_000
TOO_LARGE = "lsp-too-large"


P = TypeVar("P", bound=PurePath)
T = TypeVar("T")


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


class RungResults:
    """The per-rung results of one document's features (semantic tokens,
    symbols, folding), shared by all its versions: (feature, id(rung)) ->
    (rung, value), valid while that rung object is in the program (the reader
    keeps a rung's object while its lines stay as they are, where they are).
    A rung the reader moved up or down is a new object; its result is the old
    one's shifted, worked out when a feature first asks for it, so an edit
    that moves a thousand rungs costs nothing until then."""

    # results kept per rung of the program before the dead ones are dropped
    SLACK = 8

    def __init__(self, shifters: dict[str, Callable[[Any, int], Any]]):
        self.values: dict[tuple[str, int], tuple[Rung, object]] = {}
        self.shifters = shifters

    def get(self, feature: str, rung: Rung, origin: tuple[Rung, int] | None, compute: Callable[[], T]) -> T:
        """The feature's result for the rung: kept, the shifted one of the rung it was moved from, or computed."""
        key = (feature, id(rung))
        found = self.values.get(key)
        if found is not None and found[0] is rung:
            return cast(T, found[1])
        shift = self.shifters.get(feature)
        if origin is not None and shift is not None:
            before = self.values.get((feature, id(origin[0])))
            if before is not None and before[0] is origin[0]:
                shifted: T = shift(before[1], origin[1])
                self.values[key] = (rung, shifted)
                return shifted
        value = compute()
        self.values[key] = (rung, value)
        return value

    def prune(self, program: Program, keep: dict[int, tuple[Rung, int]]) -> None:
        """Drops the results of rungs gone (but those a moved rung still
        takes its result from), once there are many."""
        if len(self.values) <= self.SLACK * (len(program.rungs) + 100):
            return
        live = {id(rung): rung for rung in program.rungs}
        live.update((id(old), old) for old, _ in keep.values())
        self.values = {key: value for key, value in self.values.items() if live.get(key[1]) is value[0]}


class Analysis:
    """Everything known about one version of one document."""

    def __init__(self, uri: str, version: int | None, kind: str, text: str, program: Program,
                 problems: list[Diagnostic], codec: PositionCodec | None, checker: Checker | None = None,
                 moved: dict[int, tuple[Rung, int]] | None = None):
        self.uri = uri
        self.version = version
        self.kind = kind
        self.text = text
        self.program = program
        self.problems = problems  # the reader's
        self._codec = codec
        self.too_large = False
        self.severities = NONE  # the project's and the editor's choices (lang/config.py)
        self.memo = RungResults({})  # the document's, shared with its other versions
        # rung id -> (the rung of an earlier version it was moved from, by how many lines), for
        # the rungs whose results have not followed them yet
        self.moved_from: dict[int, tuple[Rung, int]] = {}
        # the text's lines and its sections' titles, as the reader split it (None: split here)
        self.split: tuple[list[str], list[tuple[str, int]]] | None = None
        self.results: dict[str, object] = {}  # whole-document results for this exact text
        self._checker = checker or Checker()  # the document's: it knows the program checked last
        # rungs moved since the program the checker checked last (ide.incremental's `moved`)
        self.moved = moved or {}
        # the locator of the version read before, if it had one, and the rungs the reader
        # moved since: the rungs' lines carry over
        self._previous_locator: tuple[Locator, dict[int, tuple[Rung, int]]] | None = None

    def per_rung(self, feature: str, index: int, compute: Callable[[int], T]) -> T:
        """The feature's result for rung `index`, kept while the rung is unchanged."""
        rung = self.program.rungs[index]
        return self.memo.get(feature, rung, self.moved_from.get(id(rung)), lambda: compute(index))

    def once(self, feature: str, compute: Callable[[], T]) -> T:
        """A whole-document result, computed once per text."""
        if feature not in self.results:
            self.results[feature] = compute()
        return cast(T, self.results[feature])

    @cached_property
    def lines(self) -> list[str]:
        return self.split[0] if self.split is not None else self.text.splitlines()

    @property
    def has_errors(self) -> bool:
        return any(p.severity == ERROR for p in self.problems)

    @cached_property
    def checks(self) -> list[Diagnostic]:
        """The checks' diagnostics, as `ladder check` gives them: for a
        program read without errors, or whose only errors are in rungs that
        could not be read (lang.loader.checkable)."""
        if self.too_large or any(p.code == codes.UNREADABLE for p in self.problems) or \
                not checkable(self.program, self.problems):
            return []
        found = self._checker.check(self.program, self.moved, self.severities)
        return checked(self.program, found) if self.has_errors else found

    @property
    def checked(self) -> bool:
        return "checks" in self.__dict__

    @property
    def diagnostics(self) -> list[Diagnostic]:
        return self.problems + self.checks

    @cached_property
    def index(self) -> ProgramIndex:
        """The symbol table: the checker's when it has checked this program
        (it is brought up to date in place by the next check: use it at once)."""
        index = self._checker.index
        if index is not None and index.program is self.program:
            return index
        return ProgramIndex(self.program)

    @cached_property
    def locator(self) -> Locator:
        previous, self._previous_locator = self._previous_locator, None
        titles = self.split[1] if self.split is not None else None
        if previous is None:
            return Locator(self.program, self.lines, self.kind, titles=titles)
        return Locator(self.program, self.lines, self.kind, *previous, titles=titles)

    @cached_property
    def positions(self) -> Positions:
        return Positions(self.lines, self._codec, self.text.isascii())

    def line(self, number: int) -> str:
        lines = self.lines
        return lines[number] if 0 <= number < len(lines) else ""


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
        program, problems = reader.read(text)
        moved = reader.moved
        if cached is not None and not cached.checked and cached.moved is not moved:
            moved = moved_since(cached.moved, program, moved)  # the version before was read, not checked
        analysis = Analysis(uri, document.version, kind, text, program, problems,
                            self.server.workspace.position_codec, self._checkers[uri], moved)
        analysis.severities = self.severities(uri)
        analysis.split = reader.split()
        analysis.memo = self._results.setdefault(uri, RungResults(self.shifters))
        if cached is not None:
            analysis.moved_from = _still_moved(cached.moved_from, program, reader.moved)
        analysis.memo.prune(program, analysis.moved_from)
        if cached is not None and cached.kind == kind and "locator" in cached.__dict__:
            analysis._previous_locator = (cached.locator, reader.moved)
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


def _still_moved(earlier: dict[int, tuple[Rung, int]], program: Program,
                 moved: dict[int, tuple[Rung, int]]) -> dict[int, tuple[Rung, int]]:
    """Where each rung of `program` whose results have not followed it comes
    from: the rungs the reader just moved (from wherever their rung of the
    version before came from), and those the version before had still to
    follow and that stayed as they were."""
    found = {}
    if earlier:
        for rung in program.rungs:
            origin = earlier.get(id(rung))
            if origin is not None:
                found[id(rung)] = origin
    for new, (old, delta) in moved.items():
        before = earlier.get(id(old))
        found[new] = (before[0], before[1] + delta) if before is not None else (old, delta)
    return found


def moved_since(earlier: dict[int, tuple[Rung, int]], program: Program,
                moved: dict[int, tuple[Rung, int]]) -> dict[int, tuple[Rung, int]]:
    """The rungs of `program` moved since the program checked last, given
    those the previous version (read, never checked) had moved, `earlier`, and
    those the reader moved since it."""
    if not earlier:
        return moved
    found = {}
    for rung in program.rungs:
        step = moved.get(id(rung))
        if step is None:
            origin = earlier.get(id(rung))  # the same rung as in the previous version
        else:
            before = earlier.get(id(step[0]))
            origin = (before[0], before[1] + step[1]) if before is not None else step
        if origin is not None:
            found[id(rung)] = origin
    return found
