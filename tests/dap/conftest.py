"""The debug adapter the HMPL tests talk to (a module may define its own `dap`)."""

from __future__ import annotations

import pytest

from tests.dap.dap_client import DapClient
from tests.dap.test_dap_hmpl import PROGRAM


@pytest.fixture
def dap(tmp_path):
    """`motionvm debug` over real pipes, in a folder holding `main.hmpl` (PROGRAM)."""
    (tmp_path / "main.hmpl").write_text(PROGRAM)
    client = DapClient(tmp_path)
    yield client
    client.close()
