"""GDL compile entry: read the files, lex, parse, check, link and lower them into an `App`."""

from __future__ import annotations

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.check import check_app
from motionvm.lang.gdl.lexer import tokenize
from motionvm.lang.gdl.lower import lower_app
from motionvm.lang.gdl.parser import parse_tokens
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile, SourcePos


def parse_file(path: str, sink: DiagnosticSink) -> n.GdlFile | None:
    """Read and parse one file; None if it cannot be read (reported to `sink`)."""
    try:
        sf = SourceFile.read(path)
    except OSError as exc:
        sink.error(SourcePos(path, 1, 1), f"cannot read the file: {exc.strerror or exc}")
        return None
    return parse_tokens(tokenize(path, sf.text, sink), path, sink)


def compile_app(paths: list[str], *, sink: DiagnosticSink) -> App | None:
    """Compile several files as one application; None when any error was reported.

    Never raises for a user's mistake: every problem becomes a diagnostic in `sink`.
    Runs with room for deep recursion (long expressions, deep nests: `run_deep`).
    """
    return run_deep(_compile_app, paths, sink)


def _compile_app(paths: list[str], sink: DiagnosticSink) -> App | None:
    try:
        files = [f for f in (parse_file(p, sink) for p in paths) if f is not None]
        if sink.has_errors:
            # Names and types are checked only on a syntactically clean application, so
            # one typo does not cascade into "unknown object" errors elsewhere.
            return None
        app = check_app(files, list(paths), sink)
        if app is not None:
            app.functions = lower_app(app)
        return app
    except TooManyErrors:
        return None
    except RecursionError:  # pragma: no cover - past 100,000 levels of nesting
        if not sink.has_errors and paths:
            sink.error(SourcePos(paths[0], 1, 1), "program nested too deeply for the compiler")
        return None
