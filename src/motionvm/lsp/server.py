"""The pygls server: capabilities, and each LSP method handed to `Features`.

A request that fails inside motionvm answers "no result" and logs the error to the
client's output: the server never stops over a document's contents."""

from __future__ import annotations

import functools
import logging
import traceback

from lsprotocol import types as t
from pygls.lsp.server import LanguageServer

from motionvm import __version__
from motionvm.lsp.features import Features

log = logging.getLogger("motionvm.lsp")

TRIGGERS = [".", ">"]
"""Completion triggers: struct members after `.` and `->`."""


def build_server() -> LanguageServer:
    server = LanguageServer("motionvm", __version__, t.TextDocumentSyncKind.Incremental)
    features = Features(
        server.text_document_publish_diagnostics, lambda: server.workspace.position_codec
    )
    server.motionvm = features  # type: ignore[attr-defined]

    def guarded(fn):
        @functools.wraps(fn)
        def run(params):
            try:
                return fn(params)
            except Exception:  # noqa: BLE001 — a bug of ours: logged, the server goes on
                message = "motionvm lsp: internal error (a bug in motionvm):\n"
                message += traceback.format_exc()
                log.error(message)
                try:
                    server.window_log_message(t.LogMessageParams(t.MessageType.Error, message))
                except Exception:  # noqa: BLE001 — the client may be gone
                    pass
                return None

        return run

    def document(ls: LanguageServer, uri: str) -> tuple[str, int | None, str | None]:
        doc = ls.workspace.get_text_document(uri)
        return doc.source, doc.version, doc.language_id

    @server.feature(t.TEXT_DOCUMENT_DID_OPEN)
    @guarded
    def did_open(params: t.DidOpenTextDocumentParams) -> None:
        d = params.text_document
        features.opened(d.uri, d.language_id, d.text, d.version)

    @server.feature(t.TEXT_DOCUMENT_DID_CHANGE)
    @guarded
    def did_change(params: t.DidChangeTextDocumentParams) -> None:
        text, version, _ = document(server, params.text_document.uri)
        features.changed(params.text_document.uri, text, version)

    @server.feature(t.TEXT_DOCUMENT_DID_CLOSE)
    @guarded
    def did_close(params: t.DidCloseTextDocumentParams) -> None:
        features.closed(params.text_document.uri)

    @server.feature(t.TEXT_DOCUMENT_HOVER)
    @guarded
    def hover(params: t.HoverParams):
        return features.hover(params)

    @server.feature(t.TEXT_DOCUMENT_COMPLETION, t.CompletionOptions(trigger_characters=TRIGGERS))
    @guarded
    def completion(params: t.CompletionParams):
        return features.completion(params)

    @server.feature(
        t.TEXT_DOCUMENT_SIGNATURE_HELP,
        t.SignatureHelpOptions(trigger_characters=["(", ","], retrigger_characters=[","]),
    )
    @guarded
    def signature_help(params: t.SignatureHelpParams):
        return features.signature_help(params)

    @server.feature(t.TEXT_DOCUMENT_DEFINITION)
    @guarded
    def definition(params: t.DefinitionParams):
        return features.definition(params)

    @server.feature(t.TEXT_DOCUMENT_REFERENCES)
    @guarded
    def references(params: t.ReferenceParams):
        return features.references(params)

    @server.feature(t.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    @guarded
    def document_symbols(params: t.DocumentSymbolParams):
        return features.document_symbols(params)

    @server.feature(t.TEXT_DOCUMENT_RENAME, t.RenameOptions(prepare_provider=True))
    @guarded
    def rename(params: t.RenameParams):
        return features.rename(params)

    @server.feature(t.TEXT_DOCUMENT_PREPARE_RENAME)
    @guarded
    def prepare_rename(params: t.PrepareRenameParams):
        return features.prepare_rename(params)

    return server
