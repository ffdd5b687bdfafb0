"""Document synchronisation and settings: didOpen/didChange/didSave/didClose
(pygls keeps the text, incremental sync) turned into the server's events,
and the `ladder` settings section."""

from __future__ import annotations

import asyncio
from typing import TYPE_CHECKING

from lsprotocol import types

from lang.textform.elements import prepare

from .settings import ladder_section

if TYPE_CHECKING:
    from .server import LadderServer


def register(server: LadderServer) -> None:
    @server.on(types.INITIALIZED)
    def initialized(ls: LadderServer, params: types.InitializedParams) -> None:
        ls.idle.start()
        prepare()
        if ls.client_supports("workspace", "configuration"):
            asyncio.ensure_future(pull_configuration(ls))

    @server.on(types.WORKSPACE_DID_CHANGE_CONFIGURATION)
    def did_change_configuration(ls: LadderServer, params: types.DidChangeConfigurationParams) -> None:
        section = ladder_section(params.settings)
        if section is not None:
            apply_settings(ls, section)
        elif ls.client_supports("workspace", "configuration"):
            asyncio.ensure_future(pull_configuration(ls))

    @server.on(types.TEXT_DOCUMENT_DID_OPEN)
    def did_open(ls: LadderServer, params: types.DidOpenTextDocumentParams) -> None:
        ls.emit("opened", params.text_document.uri)

    @server.on(types.TEXT_DOCUMENT_DID_CHANGE)
    def did_change(ls: LadderServer, params: types.DidChangeTextDocumentParams) -> None:
        ls.emit("changed", params.text_document.uri)

    @server.on(types.TEXT_DOCUMENT_DID_SAVE, types.SaveOptions(include_text=False))
    def did_save(ls: LadderServer, params: types.DidSaveTextDocumentParams) -> None:
        ls.emit("saved", params.text_document.uri)

    @server.on(types.TEXT_DOCUMENT_DID_CLOSE)
    def did_close(ls: LadderServer, params: types.DidCloseTextDocumentParams) -> None:
        ls.emit("closed", params.text_document.uri)
        ls.documents.forget(params.text_document.uri)
        ls.idle.released()


def apply_settings(ls: LadderServer, section: object) -> None:
    for problem in ls.settings.update(section):
        ls.log(problem, types.MessageType.Warning)
    ls.emit("configured", None)


async def pull_configuration(ls: LadderServer) -> None:
    try:
        result = await ls.workspace_configuration_async(
            types.ConfigurationParams(items=[types.ConfigurationItem(section="ladder")]))
    except Exception as problem:  # the client may refuse; the defaults stay
        ls.log(f"could not read the ladder settings: {problem}", types.MessageType.Warning)
        return
    if result and isinstance(result[0], dict):
        apply_settings(ls, result[0])
