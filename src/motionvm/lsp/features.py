"""The answers of the language server: LSP requests in, LSP results out, each from the
open document's current version (its check diagnostics, its index)."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from lsprotocol import types as t
from pygls import uris
from pygls.workspace.position_codec import PositionCodec

from motionvm.lang import Completion
from motionvm.lsp import convert
from motionvm.lsp.documents import Document, language_for, same_file
from motionvm.source.files import SourceFile


class Features:
    """The open documents and what the server answers about them."""

    def __init__(
        self,
        publish: Callable[[t.PublishDiagnosticsParams], None],
        codec: Callable[[], PositionCodec] = PositionCodec,
    ) -> None:
        self.publish = publish
        self.codec = codec
        """The client's position encoding (the workspace's, known after `initialize`)."""
        self.docs: dict[str, Document] = {}
        self._others: dict[str, set[str]] = {}
        """Document uri -> uris of other files (headers) it published diagnostics for."""

    # ---------------------------------------------------------------- documents

    def opened(self, uri: str, language_id: str | None, text: str, version: int | None) -> None:
        path = uris.to_fs_path(uri) or uri
        lang = language_for(path, language_id)
        if lang is None:
            return
        if Path(path).suffix.lower() not in lang.suffixes:
            path += lang.suffixes[0]  # untitled buffers: the file `check` would see
        self.docs[uri] = Document(uri, path, lang, text, version)
        self._publish(self.docs[uri])

    def changed(self, uri: str, text: str, version: int | None) -> None:
        doc = self.docs.get(uri)
        if doc is None:
            return
        self.docs[uri] = Document(uri, doc.path, doc.language, text, version)
        self._publish(self.docs[uri])

    def closed(self, uri: str) -> None:
        self.docs.pop(uri, None)
        for other in self._others.pop(uri, set()) | {uri}:
            self.publish(t.PublishDiagnosticsParams(uri=other, diagnostics=[]))

    def _publish(self, doc: Document) -> None:
        by_file: dict[str, list[t.Diagnostic]] = {doc.uri: []}
        lines = doc.lines
        codec = self.codec()
        for d in doc.diagnostics():
            if same_file(d.pos.file, doc.path):
                uri = doc.uri
                text = lines[d.pos.line - 1] if 0 < d.pos.line <= len(lines) else ""
            else:
                uri = uris.from_fs_path(str(Path(d.pos.file).resolve())) or d.pos.file
                sf = SourceFile.lookup(d.pos.file)
                text = sf.line(d.pos.line) if sf is not None else ""
            item = convert.diagnostic(d, text or "", doc.language, codec)
            by_file.setdefault(uri, []).append(item)
        stale = self._others.get(doc.uri, set()) - set(by_file)
        self._others[doc.uri] = set(by_file) - {doc.uri}
        for uri in stale:
            by_file[uri] = []
        for uri, items in by_file.items():
            self.publish(t.PublishDiagnosticsParams(uri=uri, diagnostics=items, version=None))

    # ---------------------------------------------------------------- requests

    def _at(self, params) -> tuple[Document, int, int] | None:
        doc = self.docs.get(params.text_document.uri)
        if doc is None:
            return None
        col = convert.from_client(self.codec(), doc.lines, params.position)
        return doc, params.position.line + 1, col + 1

    def _range(self, doc: Document, r: t.Range) -> t.Range:
        return convert.range_to_client(self.codec(), doc.lines, r)

    def hover(self, params: t.HoverParams) -> t.Hover | None:
        found = self._at(params)
        if found is None:
            return None
        doc, line, col = found
        text = doc.language.hover(doc.index, line, col)
        if not text:
            return None
        return t.Hover(contents=t.MarkupContent(t.MarkupKind.Markdown, text))

    def completion(self, params: t.CompletionParams) -> t.CompletionList | None:
        found = self._at(params)
        if found is None:
            return None
        doc, line, col = found
        index = doc.index
        if doc.language.inside_comment_or_literal(index.text, index.offset(line, col)):
            return t.CompletionList(is_incomplete=False, items=[])  # (no code there)
        items = doc.language.completions(index, line, col)
        return t.CompletionList(is_incomplete=False, items=[_item(c) for c in items])

    def signature_help(self, params: t.SignatureHelpParams) -> t.SignatureHelp | None:
        found = self._at(params)
        if found is None:
            return None
        doc, line, col = found
        sig = doc.language.signature(doc.index, line, col)
        return None if sig is None else convert.signature_help(*sig)

    def _symbol_at(self, params):
        found = self._at(params)
        if found is None:
            return None, None
        doc, line, col = found
        occ = doc.index.at(line, col)
        return doc, (occ.symbol if occ is not None else None)

    def definition(self, params: t.DefinitionParams) -> list[t.Location] | None:
        doc, sym = self._symbol_at(params)
        if sym is None:
            return None
        return [t.Location(doc.uri, self._range(doc, convert.symbol_range(sym)))]

    def references(self, params: t.ReferenceParams) -> list[t.Location] | None:
        doc, sym = self._symbol_at(params)
        if sym is None:
            return None
        declared = params.context.include_declaration if params.context else True
        return [
            t.Location(doc.uri, self._range(doc, convert.occurrence_range(o)))
            for o in doc.index.uses(sym)
            if declared or (o.line, o.col) != (sym.line, sym.col)
        ]

    def rename(self, params: t.RenameParams) -> t.WorkspaceEdit | None:
        doc, sym = self._symbol_at(params)
        if sym is None:
            return None
        edits = [
            t.TextEdit(self._range(doc, convert.occurrence_range(o)), params.new_name)
            for o in doc.index.uses(sym)
        ]
        return t.WorkspaceEdit(changes={doc.uri: edits})

    def prepare_rename(self, params: t.PrepareRenameParams) -> t.Range | None:
        found = self._at(params)
        if found is None:
            return None
        doc, line, col = found
        occ = doc.index.at(line, col)
        if occ is None or occ.symbol is None:
            return None
        return self._range(doc, convert.occurrence_range(occ))

    def document_symbols(self, params: t.DocumentSymbolParams) -> list[t.DocumentSymbol] | None:
        doc = self.docs.get(params.text_document.uri)
        if doc is None:
            return None
        symbols = convert.document_symbols(doc.index.symbols)
        return convert.symbols_to_client(self.codec(), doc.lines, symbols)


_ITEMS: dict[Completion, t.CompletionItem] = {}
"""LSP items of completions seen before (the documented names' are the same in every
request: made once)."""


def _item(c: Completion) -> t.CompletionItem:
    found = _ITEMS.get(c)
    if found is None:
        found = convert.completion(c)
        if len(_ITEMS) < 50_000:
            _ITEMS[c] = found
    return found
