"""A real LSP client (pytest-lsp) talking to `qcsg lsp` over stdio.

The server binary is `$QCSG_BIN`, or `target/debug/qcsg` of the repository (build it first with
`cargo build -p qcsg-cli`).
"""

import asyncio
import os
import pathlib

import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

ROOT = pathlib.Path(__file__).resolve().parents[2]
QCSG = os.environ.get("QCSG_BIN") or str(ROOT / "target" / "debug" / "qcsg")


@pytest_lsp.fixture(config=ClientServerConfig(server_command=[QCSG, "lsp"]))
async def client(lsp_client: LanguageClient, tmp_path):
    # The initialize response must arrive before anything else is sent.
    result = await lsp_client.initialize_session(
        types.InitializeParams(
            capabilities=types.ClientCapabilities(),
            root_uri=tmp_path.as_uri(),
        )
    )
    lsp_client.server_capabilities = result.capabilities
    yield
    await lsp_client.shutdown_session()


def open_document(client: LanguageClient, path: pathlib.Path, text: str, version: int = 1) -> str:
    """Opens `text` as the document at `path` (which need not exist) and returns its URI."""
    uri = path.as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="qcsg", version=version, text=text)
        )
    )
    return uri


async def diagnostics_until(client: LanguageClient, uri: str, predicate, timeout: float = 20.0):
    """Waits until the published diagnostics of `uri` satisfy `predicate`; returns them."""

    async def wait():
        while True:
            current = client.diagnostics.get(uri)
            if current is not None and predicate(current):
                return current
            await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)

    return await asyncio.wait_for(wait(), timeout)


def position_of(text: str, needle: str, nth: int = 0, shift: int = 0) -> types.Position:
    """The LSP position (UTF-16 columns) of the `nth` occurrence of `needle`, plus `shift` chars."""
    index = -1
    for _ in range(nth + 1):
        index = text.index(needle, index + 1)
    index += shift
    line = text.count("\n", 0, index)
    line_start = text.rfind("\n", 0, index) + 1
    column = len(text[line_start:index].encode("utf-16-le")) // 2
    return types.Position(line=line, character=column)
