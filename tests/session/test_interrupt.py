"""Ctrl-C ends a run cleanly: exit 130, the scope recording up to then written."""

from __future__ import annotations

import csv
import os
import re
import signal
import subprocess
import sys
import time


def test_ctrl_c_exits_130_after_writing_the_scope(tmp_path):
    (tmp_path / "a.hmpl").write_text(
        'void main() { Print("started"); for (;;) { Sleep(1); system_ltest0++; } }\n', "utf-8"
    )
    env = dict(os.environ, PYTHONUNBUFFERED="1", MOTIONVM_DATA_DIR=str(tmp_path / "data"))
    argv = [sys.executable, "-m", "motionvm", "run", "a.hmpl", "--realtime"]
    argv += ["--scope", "system_ltest0", "--scope-out", "s.csv"]
    proc = subprocess.Popen(
        argv,
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        # a test run started in the background inherits SIGINT ignored; Ctrl-C reaches a
        # program started at a terminal
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        assert proc.stdout.readline() == "started\n"  # the run is under way
        time.sleep(0.3)  # paced to the wall clock: some cycles are recorded meanwhile
        proc.send_signal(signal.SIGINT)
        _out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130
    assert "Traceback" not in err
    # at once, before the scope is written: where it stopped and what it writes
    assert re.fullmatch(
        r"motionvm: interrupted at t=\d+\.\d{3} s, writing scope s\.csv \.\.\.\n", err
    )
    rows = list(csv.reader((tmp_path / "s.csv").read_text().splitlines()))
    assert rows[0] == ["time", "system_ltest0"] and len(rows) >= 2


def test_the_interrupt_message_comes_at_once_and_the_exit_is_130(tmp_path):
    """A real SIGINT to a run that is not paced: the message is on stderr well within a
    bounded time, with no scope to write."""
    (tmp_path / "a.hmpl").write_text(
        'void main() { Print("started"); for (;;) { system_ltest0++; } }\n', "utf-8"
    )
    env = dict(os.environ, PYTHONUNBUFFERED="1", MOTIONVM_DATA_DIR=str(tmp_path / "data"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "motionvm", "run", "a.hmpl"],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        assert proc.stdout.readline() == "started\n"
        time.sleep(0.2)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        _out, err = proc.communicate(timeout=30)
        took = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130
    assert re.fullmatch(r"motionvm: interrupted at t=\d+\.\d{3} s\n", err), err
    assert took < 10
