"""Fixtures shared by the tests of every folder: the compile cache (off, or on in the
test's own folder), files written into the test's own temporary folder, the check that a bad file's error stands at its place, golden files
and their one regeneration switch (MOTIONVM_UPDATE_GOLDEN=1); the hypothesis profiles `ci` (bounded, derandomized: CI's) and `thorough` that property
tests without profiles of their own take (`settings.get_profile(...)`)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

# The compile cache stays off in the tests (their processes included): a test that
# exercises it turns it on in a temporary folder (`compile_cache` fixture). Nothing is
# written to the user's cache folder.
os.environ["MOTIONVM_NO_CACHE"] = "1"
os.environ.pop("MOTIONVM_CACHE_DIR", None)

settings.register_profile(
    "ci", max_examples=40, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "thorough", max_examples=400, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip


@pytest.fixture
def compile_cache(tmp_path, monkeypatch) -> Path:
    """The compile cache on, in a folder of the test's own (returned)."""
    folder = tmp_path / "compile-cache"
    monkeypatch.delenv("MOTIONVM_NO_CACHE", raising=False)
    monkeypatch.setenv("MOTIONVM_CACHE_DIR", str(folder))
    return folder


@pytest.fixture
def write_file(tmp_path):
    """`write_file(name, text)`: writes `text` to the file `name` in the test's folder and
    returns its path as a string (as the API and the command line take it)."""

    def write(name: str, text: str) -> str:
        path = tmp_path / name
        path.write_text(text)
        return str(path)

    return write


@pytest.fixture
def error_at():
    """`error_at(messages, path, where, message)`: the first of `messages` that contains
    `message` is an error located at `path:where` (`where` is "LINE:COL")."""

    def check(messages: list[str], path: str, where: str, message: str) -> None:
        heads = [m for m in messages if message in m]
        assert heads, messages
        assert heads[0].startswith(f"{path}:{where}: error: "), heads[0]

    return check


UPDATE_GOLDEN = "MOTIONVM_UPDATE_GOLDEN"
"""The one switch that regenerates every golden file (the `.out` files of the golden
programs, generated-Python and AST snapshots): `MOTIONVM_UPDATE_GOLDEN=1 python -m pytest`,
then review the diff."""


class Golden:
    """Golden files: compared with what a test produced, or rewritten by the switch."""

    def __init__(self) -> None:
        self.update = os.environ.get(UPDATE_GOLDEN, "") not in ("", "0")
        """Whether this run rewrites golden files instead of comparing with them."""

    def write(self, path: Path, text: str) -> None:
        """Write a golden file atomically (a temporary file renamed into place)."""
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f".{path.name}.tmp")
        tmp.write_text(text, encoding="utf-8")
        tmp.replace(path)

    def __call__(self, path: Path, text: str) -> None:
        """`text` must equal the golden file `path` (with the switch: it is written there)."""
        if self.update:
            self.write(path, text)
        assert path.is_file(), f"no golden file {path.name}: run with {UPDATE_GOLDEN}=1"
        assert text == path.read_text(encoding="utf-8"), (
            f"{path.name} differs: review the change, then rerun with {UPDATE_GOLDEN}=1"
        )


@pytest.fixture
def golden() -> Golden:
    """`golden(path, text)`: `text` must equal the golden file `path`; with
    MOTIONVM_UPDATE_GOLDEN=1 it is written there instead (`golden.update` says which)."""
    return Golden()
