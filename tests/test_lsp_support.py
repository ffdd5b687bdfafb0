"""Shared pieces of the language server's end-to-end tests (imported by the
other tests/test_lsp_*.py modules; it holds no tests itself).

Every test runs the real server (`python -m ladder lsp`) over stdio with
pytest-lsp, once per client capability profile: Neovim and VS Code. One server
per test module and profile; each test opens its own documents.
"""

from __future__ import annotations

import asyncio
import itertools
import os
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "conveyor.ladder"
PROFILES = ["neovim", "visual-studio-code"]
SERVER = [sys.executable, "-m", "ladder", "lsp"]
_counter = itertools.count()


def server_config(env: dict[str, str] | None = None) -> ClientServerConfig:
    return ClientServerConfig(server_command=SERVER, server_env={**os.environ, **(env or {})})


def lsp_fixture(env: dict[str, str] | None = None, settings: dict | None = None):
    """A module-scoped client fixture, parametrised over the client profiles."""

    @pytest_lsp.fixture(config=server_config(env), params=PROFILES, scope="module")
    async def client(request, lsp_client: LanguageClient):
        capabilities = client_capabilities(request.param)
        install_recorders(lsp_client)
        lsp_client.set_configuration({"diagnosticsDelayMs": 0, **(settings or {})}, section="ladder")
        lsp_client.init_result = await lsp_client.initialize_session(types.InitializeParams(
            capabilities=capabilities, root_uri=ROOT.as_uri(),
            workspace_folders=[types.WorkspaceFolder(uri=ROOT.as_uri(), name="main")]))
        lsp_client.profile = request.param
        # the server pulls the settings after `initialized`; let that settle
        await asyncio.sleep(0.2)
        yield
        await lsp_client.shutdown_session()

    return client


def new_uri(tmp: Path | None = None, suffix: str = ".ladder", name: str = "doc") -> str:
    folder = tmp or Path("/tmp/textladder-lsp-tests")
    return (folder / f"{name}{next(_counter)}{suffix}").as_uri()


def example_text() -> str:
    return EXAMPLE.read_text(encoding="utf-8")


def drawing_text() -> str:
    """The example without its PROPERTIES section, which a .ld file has no place for."""
    return example_text().split("\n\nPROPERTIES:")[0] + "\n"


class Doc:
    """An open document on the test client, with its version."""

    def __init__(self, client: LanguageClient, uri: str, text: str, language: str = "ladder"):
        self.client, self.uri, self.text, self.version = client, uri, text, 1
        client.text_document_did_open(types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id=language, version=1, text=text)))

    @property
    def lines(self) -> list[str]:
        return self.text.splitlines()

    def change(self, line: int, col: int, end_line: int, end_col: int, new: str) -> None:
        """An incremental change (code point columns: the tests use ASCII)."""
        lines = self.text.splitlines(keepends=True)
        start = sum(len(ln) for ln in lines[:line]) + col
        end = sum(len(ln) for ln in lines[:end_line]) + end_col
        self.text = self.text[:start] + new + self.text[end:]
        self.version += 1
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=self.uri, version=self.version),
            content_changes=[types.TextDocumentContentChangePartial(
                range=types.Range(start=types.Position(line=line, character=col),
                                  end=types.Position(line=end_line, character=end_col)),
                text=new)]))

    def replace_all(self, text: str) -> None:
        self.text = text
        self.version += 1
        self.client.text_document_did_change(types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=self.uri, version=self.version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)]))

    def apply(self, edits: list[types.TextEdit]) -> str:
        """Apply TextEdits to the local copy (as a client would) and send them."""
        text = apply_edits(self.text, edits)
        self.replace_all(text)
        return text

    def close(self) -> None:
        self.client.text_document_did_close(types.DidCloseTextDocumentParams(
            text_document=types.TextDocumentIdentifier(uri=self.uri)))

    def find(self, needle: str, occurrence: int = 0) -> types.Position:
        """Position of the n-th occurrence of a text."""
        count = 0
        for number, line in enumerate(self.lines):
            col = line.find(needle)
            while col >= 0:
                if count == occurrence:
                    return types.Position(line=number, character=col)
                count += 1
                col = line.find(needle, col + 1)
        raise AssertionError(f"{needle!r} not in the document")

    async def diagnostics(self, timeout: float = 10.0) -> list[types.Diagnostic]:
        """Wait for the diagnostics of this document's current version."""
        return await wait_diagnostics(self.client, self.uri, self.version, timeout)


async def wait_diagnostics(client: LanguageClient, uri: str, version: int | None, timeout: float = 10.0):
    loop = asyncio.get_running_loop()
    deadline = loop.time() + timeout
    while loop.time() < deadline:
        if uri in client.diagnostics and client.published_version.get(uri) == version:
            return list(client.diagnostics[uri])
        await asyncio.sleep(0.01)
    raise AssertionError(f"no diagnostics for {uri} version {version} "
                         f"(last: {client.published_version.get(uri)})")


def offset_of(text: str, position: types.Position) -> int:
    lines = text.splitlines(keepends=True)
    if position.line >= len(lines):
        return len(text)
    return sum(len(ln) for ln in lines[:position.line]) + min(position.character, len(lines[position.line]))


def apply_edits(text: str, edits: list[types.TextEdit]) -> str:
    ordered = sorted(edits, key=lambda e: (e.range.start.line, e.range.start.character), reverse=True)
    for edit in ordered:
        start, end = offset_of(text, edit.range.start), offset_of(text, edit.range.end)
        text = text[:start] + edit.new_text + text[end:]
    return text


def install_recorders(client: LanguageClient) -> None:
    """Record diagnostics versions, simulation notifications and applyEdit requests."""
    if getattr(client, "_recorders", False):
        return
    client._recorders = True
    client.published_version = {}
    client.sim_states = []
    client.applied_edits = []

    def publish(params: types.PublishDiagnosticsParams):
        client.diagnostics[params.uri] = params.diagnostics
        client.published_version[params.uri] = params.version

    def sim_state(params):
        client.sim_states.append(plain(params))

    def inlay_refresh(params):
        client.inlay_refreshes = getattr(client, "inlay_refreshes", 0) + 1

    def apply_edit(params: types.ApplyWorkspaceEditParams):
        client.applied_edits.append(params.edit)
        return types.ApplyWorkspaceEditResult(applied=True)

    features = client.protocol.fm._features  # replace pytest-lsp's defaults
    features[types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = publish
    features["ladder/simulationState"] = sim_state
    features[types.WORKSPACE_APPLY_EDIT] = apply_edit
    features[types.WORKSPACE_INLAY_HINT_REFRESH] = inlay_refresh


def plain(value):
    """pygls gives the params of a notification it does not know as namedtuples: back to JSON values."""
    if hasattr(value, "_asdict"):
        return {k: plain(v) for k, v in value._asdict().items()}
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


def hover_text(result: types.Hover | None) -> str:
    assert result is not None
    contents = result.contents
    return contents.value if hasattr(contents, "value") else str(contents)


def td(uri: str) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri=uri)


pytestmark = pytest.mark.asyncio(loop_scope="module")
