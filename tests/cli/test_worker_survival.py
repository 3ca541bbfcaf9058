"""`motionvm test` survives its workers and they do not survive it: a killed worker is
reported with its signal, a killed runner (SIGKILL) takes its workers with it, a case
printing without end is stopped at the output limit. Real processes, bounded in time."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from motionvm.cli import workers
from motionvm.cli.cases import collect
from motionvm.cli.judge import FAILED, judge

REPO = Path(__file__).resolve().parents[2]
HANG = "void main() {\n    while (1) { Sleep(1); }\n}\n// expect: never\n"
FLOOD = 'void main() {\n    while (1) { Print("flood flood flood flood flood"); }\n}\n// expect: never\n'

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="reads the process table in /proc"
)


def children(pid: int) -> list[int]:
    """The processes whose parent is `pid` (Linux /proc)."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                found.append(int(entry))
    return found


def workers_of(pid: int) -> list[int]:
    """The spawned worker processes among the children of `pid`."""
    found = []
    for child in children(pid):
        try:
            cmd = Path(f"/proc/{child}/cmdline").read_bytes()
        except OSError:
            continue
        if b"spawn_main" in cmd:
            found.append(child)
    return found


def alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def wait_for(check, seconds: float):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        value = check()
        if value:
            return value
        time.sleep(0.05)
    return check()


def start_runner(tmp_path: Path, *argv: str) -> subprocess.Popen:
    """`motionvm test` of one hanging case; its workers' temporary folders in tmp/."""
    (tmp_path / "case").mkdir()
    (tmp_path / "case" / "hang.hmpl").write_text(HANG)
    (tmp_path / "tmp").mkdir()
    env = dict(
        os.environ,
        PYTHONPATH=str(REPO / "src") + os.pathsep + os.environ.get("PYTHONPATH", ""),
        TMPDIR=str(tmp_path / "tmp"),
    )
    return subprocess.Popen(
        [sys.executable, "-m", "motionvm", "test", "-j1", *argv],
        cwd=tmp_path / "case",
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def test_a_worker_killed_by_a_signal_is_reported_as_killed(tmp_path: Path) -> None:
    runner = start_runner(tmp_path, "--case-timeout", "60")
    try:
        pids = wait_for(lambda: workers_of(runner.pid), 30)
        assert pids, "no worker started"
        # the case runs once its data folder exists
        assert wait_for(lambda: list((tmp_path / "tmp").glob("motionvm-test-*")), 60)
        started = time.monotonic()
        os.kill(pids[0], signal.SIGKILL)
        out, err = runner.communicate(timeout=30)
    finally:
        runner.kill()
    assert time.monotonic() - started < 20
    assert runner.returncode == 1, out + err
    assert "the worker running it died: killed by SIGKILL" in out
    assert "timed out" not in out


def test_killing_the_runner_ends_its_workers(tmp_path: Path) -> None:
    runner = start_runner(tmp_path, "--case-timeout", "60")
    try:
        pids = wait_for(lambda: workers_of(runner.pid), 30)
        assert pids, "no worker started"
        # the case runs once its data folder exists
        assert wait_for(lambda: list((tmp_path / "tmp").glob("motionvm-test-*")), 60)
        os.kill(runner.pid, signal.SIGKILL)
        runner.wait(timeout=10)
        start = time.monotonic()
        gone = wait_for(lambda: not any(alive(p) for p in pids), 10)
    finally:
        runner.kill()
        for p in pids:
            if alive(p):
                os.kill(p, signal.SIGKILL)
    assert gone, "a worker outlived its runner"
    assert time.monotonic() - start < 5


def test_the_parent_watch_alone_ends_an_orphan(tmp_path: Path) -> None:
    """Without the kernel's help (not Linux, or started off the main thread) the worker's
    watch thread notices it was re-parented."""
    script = (
        "import sys, time, multiprocessing as mp\n"
        "from motionvm.cli import workers\n"
        "if __name__ == '__main__':\n"
        "    ctx = mp.get_context('spawn')\n"
        "    a, b = ctx.Pipe()\n"
        "    import os\n"
        "    p = ctx.Process(target=workers._serve, args=(b, os.getpid(), False))\n"
        "    p.start(); print(p.pid, flush=True); time.sleep(60)\n"
    )
    env = dict(
        os.environ, PYTHONPATH=str(REPO / "src") + os.pathsep + os.environ.get("PYTHONPATH", "")
    )
    parent = subprocess.Popen(
        [sys.executable, "-c", script], env=env, stdout=subprocess.PIPE, text=True
    )
    try:
        pid = int(parent.stdout.readline())
        assert wait_for(lambda: alive(pid), 10)
        time.sleep(1.0)  # the worker imports motionvm and starts its watch
        parent.kill()
        parent.wait(timeout=10)
        assert wait_for(lambda: not alive(pid), 5), "the worker outlived its parent"
    finally:
        parent.kill()


def test_a_flooding_case_is_stopped_at_the_output_limit(tmp_path: Path, monkeypatch) -> None:
    (tmp_path / "flood.hmpl").write_text(FLOOD)
    monkeypatch.setattr(workers, "OUTPUT_LIMIT", 200_000)
    [case] = collect([str(tmp_path)])
    started = time.monotonic()
    outcome = workers.execute(case)
    assert time.monotonic() - started < 30
    assert outcome.flooded and len(outcome.stdout) + len(outcome.stderr) == 200_000
    verdict = judge(case, outcome, 30)
    assert verdict.status == FAILED
    assert "printed more than" in verdict.details and "endless loop" in verdict.details
    assert len(verdict.stdout) < 5000


def test_the_death_of_a_worker_in_words() -> None:
    assert workers.death(-9).startswith("killed by SIGKILL")
    assert workers.death(-15) == "killed by SIGTERM"
    assert workers.death(1) == "worker exit code 1"


def test_a_cluster_case_child_is_bounded_and_timed(tmp_path: Path, monkeypatch) -> None:
    """The path of `--dask` (each case a `python -m motionvm run` child), without Dask."""
    (tmp_path / "flood.hmpl").write_text(FLOOD)
    (tmp_path / "hang.hmpl").write_text(HANG)
    monkeypatch.setattr(workers, "OUTPUT_LIMIT", 100_000)
    flood, hang = sorted(collect([str(tmp_path)]), key=lambda c: c.id)
    outcome = workers.execute_subprocess(flood, 60)
    assert outcome.flooded and len(outcome.stdout) <= 100_000
    assert judge(flood, outcome, 60).status == FAILED
    outcome = workers.execute_subprocess(hang, 3)
    assert outcome.timed_out and outcome.wall_time < 20


def test_a_cluster_case_child_ends_with_its_parent(tmp_path: Path) -> None:
    """A Dask worker killed mid-case leaves no process behind: the `motionvm run` child
    watches the process that started it (MOTIONVM_PARENT_PID)."""
    (tmp_path / "hang.hmpl").write_text(HANG)
    script = (
        "import os, subprocess, sys, time\n"
        "env = dict(os.environ, MOTIONVM_PARENT_PID=str(os.getpid()))\n"
        "p = subprocess.Popen([sys.executable, '-m', 'motionvm', 'run', 'hang.hmpl'], env=env)\n"
        "print(p.pid, flush=True); time.sleep(60)\n"
    )
    env = dict(
        os.environ, PYTHONPATH=str(REPO / "src") + os.pathsep + os.environ.get("PYTHONPATH", "")
    )
    parent = subprocess.Popen(
        [sys.executable, "-c", script], cwd=tmp_path, env=env, stdout=subprocess.PIPE, text=True
    )
    pid = 0
    try:
        pid = int(parent.stdout.readline())
        assert wait_for(lambda: alive(pid), 10)
        time.sleep(1.5)  # the child imports motionvm and starts its watch
        parent.kill()
        parent.wait(timeout=10)
        assert wait_for(lambda: not alive(pid), 5), "the run outlived its parent"
    finally:
        parent.kill()
        if pid and alive(pid):
            os.kill(pid, signal.SIGKILL)
