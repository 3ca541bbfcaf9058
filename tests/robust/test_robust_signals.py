"""Ctrl-C (SIGINT) and SIGTERM at any moment of a run that writes a scope file.

SIGINT at seeded random moments of a scoped run: exit 130 (or 0 if the run ended
first), a scope .csv that is complete whenever one is written (equal-length rows, one
per recorded cycle; written whenever the run had started), and no temporary file left.
A signal that arrives while the interpreter itself starts, before any code of motionvm
runs, is the interpreter's: it ends the process by the signal (-SIGINT; a shell reports
that as 130 too) or as a failed start (exit 1 with the interpreter's traceback); the
moments are drawn after the interpreter's own start-up time.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import motionvm
from motionvm.sim import scope_writers
from motionvm.sim.scope import Channel, ScopeRecorder

SRC = Path(motionvm.__file__).resolve().parents[1]
TRIES = 5
"""SIGINTs sent, one per run (each run lasts ~2 s in a worktree)."""
PROGRAM = "int count;\nvoid main() {\n    while (1) {\n        count = count + 1;\n        Sleep(1);\n    }\n}\n"
ARGV = ["run", "p.hmpl", "--until", "20", "--no-skip", "--scope", "count,system_timeInMs"]


def _start(folder: Path) -> subprocess.Popen:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(SRC)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    )
    return subprocess.Popen(
        [sys.executable, "-m", "motionvm", *ARGV, "--scope-out", "o.csv"],
        cwd=folder,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )


def _check_files(folder: Path, err: str) -> int:
    """The rows of a complete o.csv (0 if none); no temporary left."""
    assert sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp")) == []
    csv = folder / "o.csv"
    if not csv.exists():
        assert "writing scope" not in err, err
        return 0
    lines = csv.read_text().splitlines()
    assert lines[0] == "time,count,system_timeInMs"
    for k, line in enumerate(lines[1:]):
        time_s, count, ms = line.split(",")  # every row complete
        assert int(ms) == k, line
        assert float(time_s) == pytest.approx(k / 1000)
    return len(lines) - 1


def test_sigint_at_random_moments_leaves_a_complete_csv(tmp_path):
    (tmp_path / "p.hmpl").write_text(PROGRAM)
    t0 = time.monotonic()
    proc = _start(tmp_path)
    out, err = proc.communicate(timeout=60)
    whole = time.monotonic() - t0
    assert proc.returncode == 0, err
    assert _check_files(tmp_path, err) == 20000
    t0 = time.monotonic()
    subprocess.run([sys.executable, "-c", "pass"], check=True)
    python_start = time.monotonic() - t0
    rng = random.Random(30)
    for _ in range(TRIES):
        (tmp_path / "o.csv").unlink(missing_ok=True)
        proc = _start(tmp_path)
        time.sleep(rng.uniform(python_start, whole * 1.05))
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
        if proc.returncode == -signal.SIGINT and "when the run ended" in err:
            # the run was over, its file written: the signal came as the interpreter exited
            assert _check_files(tmp_path, err) == 20000
            continue
        # the interpreter still starting (site, runpy, the package before its command line)
        starting = proc.returncode == -signal.SIGINT or (
            "KeyboardInterrupt" in err and "motionvm/cli/" not in err
        )
        if starting:
            assert not (tmp_path / "o.csv").exists(), err
            continue
        assert "Traceback" not in err, err
        assert proc.returncode in (130, 0), (proc.returncode, err)
        rows = _check_files(tmp_path, err)
        if proc.returncode == 0:
            assert rows == 20000


def test_sigterm_ends_a_run_without_temporaries(tmp_path):
    (tmp_path / "p.hmpl").write_text(PROGRAM)
    proc = _start(tmp_path)
    time.sleep(1.5)
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode in (143, 0, -signal.SIGTERM), err
    _check_files(tmp_path, "")


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def _aged(path: Path, age: float) -> Path:
    path.write_bytes(b"x" * 100)
    then = time.time() - age
    os.utime(path, (then, then))
    return path


def test_a_write_removes_the_temporaries_killed_writers_left(tmp_path):
    target = tmp_path / "o.csv"
    dead = _aged(tmp_path / f".o.csv.{_dead_pid()}-k3j_9x0q.tmp", 5)
    unstamped_old = _aged(tmp_path / ".o.csv.k3j_9x0q.tmp", 2 * scope_writers.STALE_AFTER)
    unstamped_new = _aged(tmp_path / ".o.csv.a1b2c3d4.tmp", 5)
    live = _aged(tmp_path / f".o.csv.{os.getpid()}-abcdefgh.tmp", 5)
    other = _aged(tmp_path / f".p.csv.{_dead_pid()}-k3j_9x0q.tmp", 5)
    with scope_writers.atomic_open(target) as f:
        f.write("time\n")
    assert target.read_text() == "time\n"
    assert not dead.exists() and not unstamped_old.exists()
    assert unstamped_new.exists() and live.exists() and other.exists()


def test_an_interrupted_write_removes_its_temporary(tmp_path):
    with pytest.raises(SystemExit), scope_writers.atomic_open(tmp_path / "o.csv") as f:
        f.write("half")
        raise SystemExit(143)  # what SIGTERM raises in a run
    assert list(tmp_path.iterdir()) == []


class _Interrupting:
    """A getter that raises KeyboardInterrupt at its `at`-th call, as Ctrl-C would."""

    def __init__(self, at: int) -> None:
        self.at, self.calls = at, 0

    def __call__(self) -> float:
        self.calls += 1
        if self.calls == self.at:
            raise KeyboardInterrupt
        return float(self.calls)


@pytest.mark.parametrize("at", [1, 2, 7, 8, 9, 17])
def test_a_sample_cut_short_is_left_out(at):
    first = [0]

    def count() -> int:
        first[0] += 1
        return first[0]

    rec = ScopeRecorder([Channel("a", "raw", count), Channel("b", "raw", _Interrupting(at))], 0.001)
    rec.CHUNK = 8  # spill to the temporary file every 8 samples
    with pytest.raises(KeyboardInterrupt):
        for cycle in range(100):
            rec.sample(cycle)
    rows = list(rec.rows())
    assert [cycle for cycle, _ in rows] == list(range(at - 1))
    assert all(len(values) == 2 for _, values in rows)
    assert len(rec) == at - 1
