"""The language interface's records as LSP's: diagnostics, symbols, completions, ranges.

Lines and columns: the interface counts from 1, LSP from 0. A column of the interface
counts characters (code points); LSP's counts the client's code units (UTF-16 unless
the client chose another encoding): `from_client` and `to_client` convert on a line."""

from __future__ import annotations

from collections.abc import Sequence

from lsprotocol import types as t
from pygls.workspace.position_codec import PositionCodec

from motionvm.lang import Completion, Language, Occurrence, Signature, Symbol
from motionvm.source.diagnostics import Diagnostic

SEVERITY = {
    "error": t.DiagnosticSeverity.Error,
    "warning": t.DiagnosticSeverity.Warning,
    "note": t.DiagnosticSeverity.Information,
}
SOURCE = "motionvm"

_COMPLETION_KIND = {
    "function": t.CompletionItemKind.Function,
    "procedure": t.CompletionItemKind.Function,
    "variable": t.CompletionItemKind.Variable,
    "parameter": t.CompletionItemKind.Variable,
    "constant": t.CompletionItemKind.Constant,
    "keyword": t.CompletionItemKind.Keyword,
    "macro": t.CompletionItemKind.Constant,
    "member": t.CompletionItemKind.Field,
    "attribute": t.CompletionItemKind.Property,
    "label": t.CompletionItemKind.Reference,
    "type": t.CompletionItemKind.Struct,
    "struct": t.CompletionItemKind.Struct,
    "module": t.CompletionItemKind.Module,
    "object": t.CompletionItemKind.Variable,
    "class": t.CompletionItemKind.Class,
}

_SYMBOL_KIND = {
    "function": t.SymbolKind.Function,
    "procedure": t.SymbolKind.Function,
    "variable": t.SymbolKind.Variable,
    "constant": t.SymbolKind.Constant,
    "macro": t.SymbolKind.Constant,
    "struct": t.SymbolKind.Struct,
    "member": t.SymbolKind.Field,
    "label": t.SymbolKind.Key,
    "task": t.SymbolKind.Namespace,
    "module": t.SymbolKind.Module,
    "object": t.SymbolKind.Object,
    "type": t.SymbolKind.TypeParameter,
    "parameter": t.SymbolKind.Variable,
}


def diagnostic(
    d: Diagnostic, line_text: str, language: Language, codec: PositionCodec
) -> t.Diagnostic:
    """An LSP diagnostic whose range covers the token the diagnostic points at (on
    `line_text`, its line)."""
    line = max(0, d.pos.line - 1)
    col = max(0, d.pos.col - 1)
    end = max(col + 1, language.token_end(line_text, d.pos.col) - 1) if line_text else col
    start, end = _units(codec, line_text, col), _units(codec, line_text, end)
    return t.Diagnostic(
        range=t.Range(t.Position(line, start), t.Position(line, end)),
        message=d.message,
        severity=SEVERITY.get(d.severity, t.DiagnosticSeverity.Information),
        source=SOURCE,
    )


def name_range(line: int, col: int, name: str) -> t.Range:
    """The range of a name written at 1-based (line, col)."""
    return t.Range(t.Position(line - 1, col - 1), t.Position(line - 1, col - 1 + len(name)))


def occurrence_range(o: Occurrence) -> t.Range:
    return name_range(o.line, o.col, o.name)


def symbol_range(s: Symbol) -> t.Range:
    """The range of a declaration's name (a struct's `struct T`: of T)."""
    return name_range(s.line, s.col, s.name.rsplit(" ", 1)[-1])


def document_symbols(symbols: list[Symbol]) -> list[t.DocumentSymbol]:
    """The outline: file-level declarations, each with the objects, procedures and members
    it contains (a function's locals are left out)."""
    top: dict[str, t.DocumentSymbol] = {}
    out: list[t.DocumentSymbol] = []
    for s in symbols:
        if s.container is None:
            ds = _document_symbol(s)
            out.append(ds)
            top.setdefault(s.name, ds)
    for s in symbols:
        if s.container is not None and s.kind in ("object", "procedure", "member"):
            parent = top.get(s.container)
            child = _document_symbol(s)
            if parent is None:
                out.append(child)
            else:
                parent.children = [*(parent.children or []), child]
    return out


def _document_symbol(s: Symbol) -> t.DocumentSymbol:
    sel = symbol_range(s)
    full = t.Range(sel.start, t.Position(max(s.end_line, s.line) - 1, sel.end.character))
    if s.end_line > s.line:
        full = t.Range(t.Position(s.line - 1, 0), t.Position(s.end_line, 0))
    return t.DocumentSymbol(
        name=s.name.rsplit(" ", 1)[-1] if s.kind == "struct" else s.name,
        kind=_SYMBOL_KIND.get(s.kind, t.SymbolKind.Variable),
        range=full,
        selection_range=sel,
        detail=s.detail or None,
    )


def completion(c: Completion) -> t.CompletionItem:
    return t.CompletionItem(
        label=c.label,
        kind=_COMPLETION_KIND.get(c.kind, t.CompletionItemKind.Text),
        detail=c.detail or None,
        documentation=t.MarkupContent(t.MarkupKind.Markdown, c.doc) if c.doc else None,
        insert_text=c.snippet or None,
        insert_text_format=t.InsertTextFormat.Snippet if c.snippet else None,
    )


def signature_help(sig: Signature, arg: int) -> t.SignatureHelp:
    params = [t.ParameterInformation(label=(a, b)) for a, b in sig.params]
    active = min(arg, len(params) - 1) if params else 0
    info = t.SignatureInformation(
        label=sig.label,
        documentation=t.MarkupContent(t.MarkupKind.Markdown, sig.doc) if sig.doc else None,
        parameters=params,
        active_parameter=active,
    )
    return t.SignatureHelp(signatures=[info], active_signature=0, active_parameter=active)


def from_client(codec: PositionCodec, lines: Sequence[str], pos: t.Position) -> int:
    """The 0-based character column of a client's position (past the end: as far past)."""
    if not 0 <= pos.line < len(lines):
        return pos.character
    units = 0
    for i, ch in enumerate(lines[pos.line]):
        if units >= pos.character:
            return i
        units += codec.client_num_units(ch)
    return len(lines[pos.line]) + max(0, pos.character - units)


def to_client(codec: PositionCodec, lines: Sequence[str], pos: t.Position) -> t.Position:
    """A position of characters as the client counts it."""
    if not 0 <= pos.line < len(lines):
        return pos
    return t.Position(pos.line, _units(codec, lines[pos.line], pos.character))


def _units(codec: PositionCodec, text: str, col: int) -> int:
    """The client's code units before 0-based character `col` of `text`."""
    return codec.client_num_units(text[:col]) + max(0, col - len(text))


def range_to_client(codec: PositionCodec, lines: Sequence[str], r: t.Range) -> t.Range:
    return t.Range(to_client(codec, lines, r.start), to_client(codec, lines, r.end))


def symbols_to_client(
    codec: PositionCodec, lines: Sequence[str], symbols: list[t.DocumentSymbol]
) -> list[t.DocumentSymbol]:
    """Document symbols (and their children) with ranges as the client counts them."""
    for s in symbols:
        s.range = range_to_client(codec, lines, s.range)
        s.selection_range = range_to_client(codec, lines, s.selection_range)
        symbols_to_client(codec, lines, s.children or [])
    return symbols
