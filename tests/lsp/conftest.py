"""A running `motionvm lsp` per test, initialized, shut down afterwards."""

from __future__ import annotations

from pathlib import Path

import pytest
from lsp_client import LspClient


@pytest.fixture
def lsp(tmp_path):
    client = LspClient(cwd=tmp_path)
    client.initialize()
    yield client
    assert client.close() == 0, b"".join(client.stderr).decode()


@pytest.fixture
def doc(tmp_path):
    """`doc(name, text)`: writes the file and returns its uri."""

    def write(name: str, text: str) -> str:
        path = tmp_path / name
        path.write_text(text)
        return Path(path).resolve().as_uri()

    return write
