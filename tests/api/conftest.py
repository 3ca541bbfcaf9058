"""Fixtures of the host API tests."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture(autouse=True)
def data_dir(tmp_path, monkeypatch) -> Path:
    """Each test's user table in its own folder."""
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    return tmp_path
