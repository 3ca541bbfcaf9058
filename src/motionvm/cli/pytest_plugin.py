"""pytest plugin: `python -m pytest --motionvm PATHS` collects the cases `motionvm test
PATHS` does (cli/cases.py) as pytest items, so pytest's `-k`, `--lf`, `-x`,
`--durations`, `--junitxml`, pytest-xdist's `-n` and IDE test panels see them.

Installed with the package (entry point `pytest11`), it does nothing unless asked:
`--motionvm` on the command line, or `motionvm = true` in the `[pytest]` ini section.
A project's own Python tests are collected as before. Each case runs like a case of
`motionvm test`: in a worker process of its own (cli/workers.py), judged by
cli/judge.py, within `--motionvm-case-timeout` seconds.
"""

from __future__ import annotations

from pathlib import Path

import pytest


def pytest_addoption(parser) -> None:
    group = parser.getgroup("motionvm", "machine programs with expectations (motionvm test)")
    group.addoption(
        "--motionvm",
        action="store_true",
        default=False,
        help="collect the programs that carry expectations (.hmpl, .pdl, .gdl) as tests",
    )
    group.addoption(
        "--motionvm-case-timeout",
        type=float,
        default=60.0,
        metavar="S",
        help="wall-clock time limit of one motionvm case (default 60 s)",
    )
    parser.addini(
        "motionvm", "collect motionvm cases as with --motionvm", type="bool", default=False
    )


def _enabled(config) -> bool:
    return bool(config.getoption("motionvm") or config.getini("motionvm"))


def pytest_collect_file(file_path: Path, parent):
    if not _enabled(parent.config):
        return None
    from motionvm.cli.cases import is_case_file

    if not is_case_file(file_path):
        return None
    rel = (
        file_path.relative_to(parent.config.rootpath)
        if file_path.is_relative_to(parent.config.rootpath)
        else file_path
    )
    if any(part.startswith(("__", ".")) for part in rel.parts[:-1]):
        return None  # as `motionvm test`: no hidden folders, no __pycache__
    return CaseFile.from_parent(parent, path=file_path)


class CaseFile(pytest.File):
    """A program file: one case if it carries expectations, none otherwise."""

    def collect(self):
        from motionvm.cli.cases import make_case

        case = make_case(self.path, self.path.name)
        if case is not None:
            yield CaseItem.from_parent(self, name=self.path.stem, case=case)


class CaseFailed(Exception):
    """A case's verdict was failed or error; its details are the report."""


class CaseItem(pytest.Item):
    """One case of `motionvm test`."""

    def __init__(self, *, case, **kwargs) -> None:
        super().__init__(**kwargs)
        self.case = case

    def runtest(self) -> None:
        from motionvm.cli import workers
        from motionvm.cli.judge import ERROR, FAILED, XFAILED, judge

        timeout = self.config.getoption("motionvm_case_timeout")
        outcome = None
        if self.case.problem is None:
            stream = workers.local_outcomes([self.case], 1, timeout)
            outcome = next(outcome for _, outcome in stream)
            stream.close()
        verdict = judge(self.case, outcome, timeout)
        if verdict.status == XFAILED:
            pytest.xfail(verdict.details)
        if verdict.status in (FAILED, ERROR):
            text = verdict.details.rstrip("\n")
            if verdict.stderr.strip():
                text += "\n--- stderr ---\n" + verdict.stderr.rstrip("\n")
            raise CaseFailed(text)

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, CaseFailed):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return self.path, None, f"motionvm case {self.case.id}"
