"""Fixtures of the communication tests."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def data_dir(tmp_path, monkeypatch):
    """Each test's user table in its own folder."""
    monkeypatch.setenv("MOTIONVM_DATA_DIR", str(tmp_path))
    return tmp_path
