"""Running `motionvm.cli.main` in-process on files of a temporary folder, for the tests of
bad input from outside (each must be a clear error, never an internal one)."""

from __future__ import annotations

import contextlib
import io
import os
from dataclasses import dataclass
from pathlib import Path

import pytest


@dataclass
class Outcome:
    code: int
    stdout: str
    stderr: str


class Cli:
    """`cli(*argv, **files)`: writes `files` (name: text) into the folder, then runs the
    command there and returns its exit code and output."""

    def __init__(self, folder: Path):
        self.folder = folder

    def __call__(self, *argv: str, **files: str) -> Outcome:
        from motionvm.cli import main

        for name, text in files.items():
            (self.folder / name.replace("__", ".")).write_text(text, encoding="utf-8")
        out, err = io.StringIO(), io.StringIO()
        old = Path.cwd()
        os.chdir(self.folder)
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                code = main(list(argv))
        finally:
            os.chdir(old)
        assert "Traceback" not in err.getvalue(), err.getvalue()
        return Outcome(code, out.getvalue(), err.getvalue())


@pytest.fixture
def cli(tmp_path):
    return Cli(tmp_path)
