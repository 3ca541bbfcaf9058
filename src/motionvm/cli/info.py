"""`motionvm dump`: what each compiler stage makes of a file."""

from __future__ import annotations

import sys
from pathlib import Path

from motionvm.cli.exits import EXIT_COMPILE, EXIT_OK, UsageError
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic


def cmd_dump(args) -> int:
    path, stage = args.file, args.stage
    suffix = Path(path).suffix.lower()
    if not Path(path).is_file():
        raise UsageError(f"{path}: no such file")
    if suffix == ".gdl":
        return _gdl_dump(path, stage)
    if suffix == ".pdl":
        return _pdl_dump(path, stage)
    if suffix != ".hmpl":
        raise UsageError(f"unknown file type '{suffix}' (expected .hmpl, .pdl or .gdl)")
    return _hmpl_dump(path, stage, args.task_id)


def _report(items) -> None:
    for d in items:
        print(render_diagnostic(d), file=sys.stderr)


def _hmpl_dump(path: str, stage: str, task_id: int) -> int:
    from motionvm.lang.hmpl import dump
    from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
    from motionvm.lang.hmpl.parser import parse
    from motionvm.lang.hmpl.preprocess import preprocess

    sink = DiagnosticSink()
    if stage == "py":
        prog, _mem = compile_tasks([TaskFile(0, path)], sink)
        _report(sink.items)
        if prog is None:
            return EXIT_COMPILE
        sys.stdout.write(prog.python_source())
        return EXIT_OK
    toks = preprocess(path, task_id=task_id, sink=sink)
    if stage == "tokens":
        sys.stdout.write(dump.dump_tokens(toks) + "\n")
    else:
        tu = parse(toks, sink)
        sys.stdout.write(dump.dump_ast(tu) + "\n")
    _report(sink.items)
    return EXIT_COMPILE if sink.has_errors else EXIT_OK


def _pdl_dump(path: str, stage: str) -> int:
    from motionvm.lang.pdl import dump
    from motionvm.lang.pdl.front import compile_front
    from motionvm.lang.pdl.preprocess import preprocess

    sink = DiagnosticSink()
    if stage == "tokens":
        sys.stdout.write(dump.dump_tokens(preprocess(path, sink)) + "\n")
    elif stage == "ast":
        prog = compile_front(path, sink=sink)
        if prog is not None:
            sys.stdout.write(dump.dump_ast(prog) + "\n")
    else:
        from motionvm.lang.pdl.program import compile_pdl

        prog = compile_pdl(path, sink=sink)
        if prog is not None:
            sys.stdout.write(prog.python_source() + "\n")
    _report(sorted(sink.items, key=lambda d: (d.pos.file, d.pos.line, d.pos.col)))
    return EXIT_COMPILE if sink.has_errors else EXIT_OK


def _gdl_dump(path: str, stage: str) -> int:
    from motionvm.lang.gdl.compiler import compile_app
    from motionvm.lang.gdl.dump import dump_ast, dump_tokens
    from motionvm.lang.gdl.lower import emit_python

    sink = DiagnosticSink()
    if stage == "py":
        app = compile_app([path], sink=sink)
        _report(sorted(sink.items, key=lambda d: (d.pos.line, d.pos.col)))
        if app is None:
            return EXIT_COMPILE
        sys.stdout.write(emit_python(app))
        return EXIT_OK
    try:
        sys.stdout.write((dump_tokens if stage == "tokens" else dump_ast)(path, sink))
    except OSError as exc:
        print(f"error: cannot read {path}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_COMPILE
    _report(sink.items)
    return EXIT_COMPILE if sink.has_errors else EXIT_OK
