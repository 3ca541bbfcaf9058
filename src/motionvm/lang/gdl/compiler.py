"""GDL compile entry: read the files, lex, parse, check, link and lower them into an `App`."""

from __future__ import annotations

from collections.abc import Mapping
from types import CodeType
from typing import TYPE_CHECKING

from motionvm.lang.gc_hold import gc_held
from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.check import check_app
from motionvm.lang.gdl.lexer import tokenize
from motionvm.lang.gdl.lower import compile_app_code, load_app_code
from motionvm.lang.gdl.parser import parse_tokens
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile, SourcePos

if TYPE_CHECKING:
    from motionvm.source.cache import CompileCache


def parse_file(path: str, sink: DiagnosticSink, text: str | None = None) -> n.GdlFile | None:
    """Read and parse one file (or `text` under its name); None if it cannot be read
    (reported to `sink`)."""
    if text is not None:
        if "\r" in text:  # as SourceFile.read does: CRLF and CR line ends become LF
            text = text.replace("\r\n", "\n").replace("\r", "\n")
        sf = SourceFile.register(path, text)
        return parse_tokens(tokenize(path, sf.text, sink), path, sink)
    try:
        sf = SourceFile.read(path)
    except OSError as exc:
        sink.error(SourcePos(path, 1, 1), f"cannot read the file: {exc.strerror or exc}")
        return None
    return parse_tokens(tokenize(path, sf.text, sink), path, sink)


def compile_app(
    paths: list[str],
    *,
    sink: DiagnosticSink,
    texts: Mapping[str, str] | None = None,
    cache: CompileCache | None = None,
) -> App | None:
    """Compile several files as one application; None when any error was reported.
    `texts`: the contents of files by path, instead of reading them. With a `cache` an
    unchanged application is read from it, and a newly compiled one stored in it
    (`app_cache.py`).

    Never raises for a user's mistake: every problem becomes a diagnostic in `sink`.
    Runs with room for deep recursion (long expressions, deep nests: `run_deep`).
    """
    texts = texts or {}
    if cache is None:
        return run_deep(_compile_app, paths, sink, texts, None)
    # (reading and storing an entry walk the syntax trees: deep ones need the room too)
    return run_deep(_compile_cached, paths, sink, texts, cache)


def _compile_cached(
    paths: list[str], sink: DiagnosticSink, texts: Mapping[str, str], cache: CompileCache
) -> App | None:
    from motionvm.lang.gdl import app_cache

    key = app_cache.app_key(paths, texts)
    if key is None:  # a file cannot be read: the compile reports it
        return run_deep(_compile_app, paths, sink, texts, None)
    app = app_cache.load(cache, key, texts, sink)
    if app is None:
        first = len(sink.items)
        codes: list[tuple[str, CodeType]] = []
        app = run_deep(_compile_app, paths, sink, texts, codes)
        if app is not None:
            app_cache.store(cache, key, app, codes, sink.items[first:])
    return app


def _compile_app(
    paths: list[str],
    sink: DiagnosticSink,
    texts: Mapping[str, str],
    codes: list[tuple[str, CodeType]] | None,
) -> App | None:
    try:
        with gc_held():
            parsed = (parse_file(p, sink, texts.get(p)) for p in paths)
            files = [f for f in parsed if f is not None]
            if sink.has_errors:
                # Names and types are checked only on a syntactically clean application, so
                # one typo does not cascade into "unknown object" errors elsewhere.
                return None
            app = check_app(files, list(paths), sink)
            if app is not None:
                compiled = compile_app_code(app)
                if codes is not None:
                    codes.extend(compiled)
                app.functions = load_app_code(app, compiled)
            return app
    except TooManyErrors:
        return None
    except RecursionError:  # pragma: no cover - past 100,000 levels of nesting
        if not sink.has_errors and paths:
            sink.error(SourcePos(paths[0], 1, 1), "program nested too deeply for the compiler")
        return None
