"""Fixtures shared by the tests of every folder: files written into the test's own
temporary folder, and the check that a bad file's error stands at its place; the
hypothesis profiles `ci` (bounded, derandomized: CI's) and `thorough` that property
tests without profiles of their own take (`settings.get_profile(...)`)."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", max_examples=40, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip
settings.register_profile(
    "thorough", max_examples=400, derandomize=True, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)  # fmt: skip


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
