"""examples/05_hmi.py drives examples/05_hmi.hmpl under `motionvm serve` (free ports)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
from pathlib import Path

from comm_helpers import WAIT

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_the_example_hmi_drives_the_served_program(tmp_path):
    (tmp_path / "m.toml").write_text(
        "[comm]\nnative_ascii_port = 0\nuser_ascii_port = 0\nmodbus_port = 0\n"
    )
    env = dict(os.environ, MOTIONVM_DATA_DIR=str(tmp_path))
    serve = subprocess.Popen(
        [sys.executable, "-m", "motionvm", "serve", "--machine", "m.toml",
         str(EXAMPLES / "05_hmi.hmpl")],
        cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
    )  # fmt: skip
    timer = threading.Timer(120, serve.kill)  # bounded, whatever happens
    timer.start()
    try:
        ports = {}
        while len(ports) < 3:
            line = serve.stderr.readline()  # type: ignore[union-attr]
            m = re.fullmatch(r"(\S+) listening on 127\.0\.0\.1:(\d+)\n", line)
            assert m, line
            ports[m.group(1)] = m.group(2)
        hmi = subprocess.run(
            [sys.executable, str(EXAMPLES / "05_hmi.py"), "25.5", "-12",
             "--modbus-port", ports["modbus"], "--native-port", ports["native-ascii"],
             "--user-port", ports["user-ascii"]],
            capture_output=True, text=True, timeout=WAIT * 6, env=env,
        )  # fmt: skip
        serve.send_signal(signal.SIGINT)
        out, err = serve.communicate(timeout=WAIT * 3)
    finally:
        timer.cancel()
        serve.kill()
    assert hmi.returncode == 0, hmi.stderr
    lines = hmi.stdout.splitlines()
    assert lines[0].startswith("target 25.5: axis 0 at 25.5 mm, outputs 1-8 [")
    assert lines[1].startswith("target -12: axis 0 at -12 mm, outputs 1-8 [")
    assert lines[2:] == [
        "user ascii: jobs 2 pos -12.000",
        "native ascii: GetPosFb(0) = -12.0",
    ]
    assert serve.returncode == 0, err
    assert out.splitlines() == ["ready", "job 1: axis 0 at 25.500", "job 2: axis 0 at -12.000"]
