"""`motionvm dump`: what each compiler stage makes of a file."""

from __future__ import annotations

import sys
from pathlib import Path

from motionvm.cli.exits import EXIT_COMPILE, EXIT_OK, UsageError
from motionvm.lang import LanguageInputError, language_of, suffix_list
from motionvm.source.diagnostics import render_diagnostic
from motionvm.source.files import why_unreadable


def cmd_dump(args) -> int:
    path, stage = args.file, args.stage
    if not Path(path).is_file():
        raise UsageError(f"{path}: {why_unreadable(path)}")
    lang = language_of(path)
    if lang is None:
        suffix = Path(path).suffix.lower()
        raise UsageError(f"unknown file type '{suffix}' (expected {suffix_list()})")
    try:
        text, diagnostics = lang.dump(path, stage, {"task_id": args.task_id})
    except LanguageInputError as exc:
        print(exc, file=sys.stderr)
        return EXIT_COMPILE
    sys.stdout.write(text)
    for d in diagnostics:
        print(render_diagnostic(d), file=sys.stderr)
    return EXIT_COMPILE if any(d.severity == "error" for d in diagnostics) else EXIT_OK
