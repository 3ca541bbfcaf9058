"""`motionvm studio` as a command: one line with the page's address on stderr, nothing
else with `http://`, the page answers, Ctrl-C exits 0; a bad command line exits 3."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import motionvm
from tests.studio.studio_client import EXAMPLES, TIMEOUT_S

LINE = re.compile(r"motionvm studio: http://127\.0\.0\.1:(\d+)/\?token=([\w-]+)")


def _env(tmp_path: Path) -> dict[str, str]:
    env = dict(os.environ)
    src = str(Path(motionvm.__file__).resolve().parents[1])
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["MOTIONVM_DATA_DIR"] = str(tmp_path)
    return env


def test_the_command_prints_its_address_serves_the_page_and_ends_on_ctrl_c(tmp_path):
    proc = subprocess.Popen(
        [sys.executable, "-m", "motionvm", "studio", "--no-browser", "--port", "0",
         str(EXAMPLES / "01_hello.hmpl")],
        stderr=subprocess.PIPE, stdout=subprocess.PIPE, env=_env(tmp_path), text=True,
    )  # fmt: skip
    try:
        first = proc.stderr.readline()
        found = LINE.fullmatch(first.strip())
        assert found, first
        url = first.split(": ", 1)[1].strip()
        with urllib.request.urlopen(url, timeout=TIMEOUT_S) as page:
            assert page.status == 200 and b"motionvm studio" in page.read()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=TIMEOUT_S)
    finally:
        proc.kill()
    assert proc.returncode == 0, err
    assert "http://" not in err and "Traceback" not in err
    assert out == ""


def test_a_missing_file_or_machine_is_a_usage_error(tmp_path):
    for args in (["nope.hmpl"], ["--machine", "nope.toml", str(EXAMPLES / "01_hello.hmpl")]):
        done = subprocess.run(
            [sys.executable, "-m", "motionvm", "studio", "--no-browser", *args],
            capture_output=True, text=True, env=_env(tmp_path), timeout=TIMEOUT_S,
        )  # fmt: skip
        assert done.returncode == 3, done.stderr
        assert "nope" in done.stderr and "Traceback" not in done.stderr
