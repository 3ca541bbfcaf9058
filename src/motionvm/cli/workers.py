"""Where the cases of `motionvm test` run: a pool of worker processes, or a Dask cluster.

A local worker runs one case at a time in its own process, through the command line's
`main` with stdout and stderr captured, in the case's folder, with a fresh data folder
(MOTIONVM_DATA_DIR). Before it runs a case it imports the run path and the compilers
of the case's languages, and only then does the case's wall-clock time limit start: it
measures the case's own run, not a first import (over a second on a busy machine). A
case that exceeds its limit has its worker killed and replaced while cases remain, so a
program that never ends fails instead of hanging the suite.
On a Dask cluster each case runs as `python -m motionvm run` in a subprocess of a Dask
worker (the workers need motionvm installed and the same paths to the programs).
"""

from __future__ import annotations

import contextlib
import importlib
import io
import multiprocessing
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from pathlib import Path

from motionvm.cli.cases import Case
from motionvm.lang import LANGUAGES, language_of

_READY = "ready"
_RUNNING = "running"
_START_TIMEOUT_S = 120.0
"""Wall-clock time a new worker process may take to start and import motionvm [s]."""
_RUN_MODULES = ("motionvm.cli.run", "motionvm.session")
"""What every run imports."""


def preload_modules(cases: Sequence[Case]) -> tuple[str, ...]:
    """The modules a worker imports before the clock of a case starts: the run path and
    the languages of the program files the cases name."""
    used = {language_of(arg) for case in cases for arg in case.argv}
    langs = [m for lang in LANGUAGES if lang in used for m in lang.run_modules]
    return (*_RUN_MODULES, *langs)


@dataclass(frozen=True)
class Outcome:
    """What one run of a case did."""

    returncode: int | None
    stdout: str
    stderr: str
    wall_time: float
    """Wall-clock duration of the run [s]."""
    timed_out: bool = False
    crashed: str | None = None
    """Why the worker running the case died (the case could not be judged)."""
    coverage: dict | None = None
    """The coverage data of the case's runs, merged (when asked for)."""


def runs(case: Case) -> list[list[str]]:
    """The command lines of a case after `motionvm`: its run (or check), and the run after
    the power cycle of a `restart:`."""
    return [[case.command, *case.argv]] + ([["run", *case.restart]] if case.restart else [])


def _combined(codes: list[int], expected: int) -> int:
    """The exit code of a case's runs: the first that is not the expected one, else it."""
    return next((c for c in codes if c != expected), codes[-1])


def execute(case: Case, coverage: bool = False) -> Outcome:
    """Run `case` in this process: `motionvm run ARGV` (or `check`) in its folder, output
    captured. A restart runs only if the first run ended as expected; both share one data
    folder. `coverage`: the runs count coverage, merged into `Outcome.coverage`."""
    from motionvm.cli import run as run_module
    from motionvm.cli.entry import run_command
    from motionvm.cli.run import cmd_check, cmd_run
    from motionvm.lang.coverage import merge

    commands = {"run": cmd_run, "check": cmd_check}
    out, err = io.StringIO(), io.StringIO()
    cwd, data_env = os.getcwd(), os.environ.get("MOTIONVM_DATA_DIR")
    start = time.perf_counter()
    codes: list[int] = []
    sink: list | None = [] if coverage else None
    with tempfile.TemporaryDirectory(prefix="motionvm-test-") as data:
        os.environ["MOTIONVM_DATA_DIR"] = data
        run_module.COVERAGE_SINK = sink
        try:
            os.chdir(case.folder)
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                for argv in runs(case):
                    if codes and codes[-1] != case.expect.exit_code:
                        break
                    codes.append(run_command(argv, commands[argv[0]]))
        finally:
            run_module.COVERAGE_SINK = None
            os.chdir(cwd)
            if data_env is None:
                os.environ.pop("MOTIONVM_DATA_DIR", None)
            else:
                os.environ["MOTIONVM_DATA_DIR"] = data_env
    code = _combined(codes, case.expect.exit_code)
    merged = None
    if sink is not None:
        merged = {}
        for d in sink:
            merge(merged, d)
    return Outcome(
        code, out.getvalue(), err.getvalue(), time.perf_counter() - start, coverage=merged
    )


def execute_subprocess(case: Case, timeout: float, coverage: bool = False) -> Outcome:
    """Run `case` as `python -m motionvm run ARGV` in a child process (Dask workers)."""
    import motionvm

    env = dict(os.environ)
    src = str(Path(motionvm.__file__).resolve().parents[1])
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    start = time.perf_counter()
    codes: list[int] = []
    out, err = [], []
    merged: dict | None = {} if coverage else None
    with tempfile.TemporaryDirectory(prefix="motionvm-test-") as data:
        env["MOTIONVM_DATA_DIR"] = data
        cov_file = os.path.join(data, ".coverage.json")
        for argv in runs(case):
            if codes and codes[-1] != case.expect.exit_code:
                break
            if coverage and argv[0] == "run":
                argv = [argv[0], "--cov-report", f"json:{cov_file}", *argv[1:]]
            left = timeout - (time.perf_counter() - start)
            try:
                proc = subprocess.run(
                    [sys.executable, "-m", "motionvm", *argv],
                    cwd=case.folder,
                    env=env,
                    capture_output=True,
                    text=True,
                    encoding="utf-8",
                    errors="replace",
                    timeout=max(left, 0.001),
                    check=False,
                )
            except subprocess.TimeoutExpired as exc:
                out.append(_text(exc.stdout))
                err.append(_text(exc.stderr))
                return Outcome(None, "".join(out), "".join(err), time.perf_counter() - start, True)
            codes.append(proc.returncode)
            out.append(proc.stdout)
            err.append(proc.stderr)
            if merged is not None and os.path.exists(cov_file):
                from motionvm.cli.coverage import read_json
                from motionvm.lang.coverage import merge

                merge(merged, read_json(cov_file))
                os.unlink(cov_file)
    code = _combined(codes, case.expect.exit_code)
    return Outcome(code, "".join(out), "".join(err), time.perf_counter() - start, coverage=merged)


def _text(data: bytes | str | None) -> str:
    if isinstance(data, bytes):
        return data.decode("utf-8", "replace")
    return data or ""


def _serve(conn: Connection) -> None:
    """A worker process: for each case it receives, import what the case needs, say it
    runs, run it and send back its Outcome; None ends it."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    import motionvm.cli.entry  # noqa: F401 — imported once, before the first case's clock starts

    conn.send(_READY)
    while True:
        job = conn.recv()
        if job is None:
            return
        case, coverage = job
        try:
            for name in preload_modules([case]):  # before the case's clock starts
                importlib.import_module(name)
            conn.send(_RUNNING)
            conn.send(execute(case, coverage))
        except Exception as exc:  # noqa: BLE001 — reported as the case's crash
            conn.send(Outcome(None, "", "", 0.0, crashed=f"{type(exc).__name__}: {exc}"))


class _Worker:
    """One worker process and the case it is running."""

    def __init__(self, ctx) -> None:
        self.conn, child = ctx.Pipe()
        self.process = ctx.Process(target=_serve, args=(child,), daemon=True)
        self.process.start()
        child.close()
        self.ready = False
        self.index: int | None = None
        self.deadline = time.monotonic() + _START_TIMEOUT_S
        self.started = 0.0
        self.timeout = 0.0

    def send(self, index: int, case: Case, timeout: float, coverage: bool = False) -> None:
        """Hand `case` over; its `timeout` starts when the worker says it runs it."""
        self.index = index
        self.timeout = timeout
        self.started = time.perf_counter()
        self.deadline = time.monotonic() + _START_TIMEOUT_S  # the imports of its languages
        try:
            self.conn.send((case, coverage))
        except OSError:  # the worker died while idle: its sentinel reports it next
            pass

    def kill(self) -> None:
        if self.process.is_alive():
            self.process.kill()
        self.process.join()
        self.conn.close()

    def stop(self) -> None:
        try:
            self.conn.send(None)
        except OSError:
            pass
        self.process.join(timeout=2)
        self.kill()


def local_outcomes(
    cases: Sequence[Case], jobs: int, timeout: float, coverage: bool = False
) -> Iterator[tuple[int, Outcome]]:
    """(index, outcome) of each case, in the order they finish, on `jobs` processes."""
    ctx = multiprocessing.get_context("spawn")  # a clean interpreter, whatever the parent did
    todo = list(range(len(cases)))[::-1]
    workers = [_Worker(ctx) for _ in range(min(jobs, len(cases)))]
    try:
        while todo or any(w.index is not None for w in workers):
            for w in workers:
                if w.ready and w.index is None and todo:
                    i = todo.pop()
                    w.send(i, cases[i], timeout, coverage)
            live = [w for w in workers if not w.ready or w.index is not None]
            wait_s = max(0.0, min(w.deadline for w in live) - time.monotonic())
            ready = set(wait([w.conn for w in live] + [w.process.sentinel for w in live], wait_s))
            for k, w in enumerate(workers):
                if w not in live:
                    continue
                message = _receive(w.conn) if w.conn in ready else None
                if message == _READY:
                    w.ready = True
                    continue
                if message == _RUNNING:  # the case's clock starts now
                    w.started = time.perf_counter()
                    w.deadline = time.monotonic() + w.timeout
                    continue
                if isinstance(message, Outcome):
                    index, w.index = w.index, None
                    yield index, message
                    continue
                dead = w.conn in ready or w.process.sentinel in ready
                if dead or time.monotonic() >= w.deadline:
                    if w.index is None:
                        raise RuntimeError("a worker process of 'motionvm test' did not start")
                    index, lost = w.index, _lost(w)
                    w.kill()
                    w.index = None  # a dead worker is not live: no case, and ready
                    if todo:  # a replacement only while cases wait for one
                        workers[k] = _Worker(ctx)
                    yield index, lost
    finally:
        for w in workers:
            if w.index is None and w.process.is_alive():
                w.stop()
            else:
                w.kill()


def _receive(conn: Connection):
    """The next message on `conn`; None if the worker is gone."""
    try:
        return conn.recv()
    except (EOFError, OSError):
        return None


def _lost(w: _Worker) -> Outcome:
    """The outcome of the case of a worker that timed out or died."""
    elapsed = time.perf_counter() - w.started
    if w.process.is_alive():
        return Outcome(None, "", "", elapsed, timed_out=True)
    w.process.join()
    return Outcome(None, "", "", elapsed, crashed=f"worker exit code {w.process.exitcode}")


class DaskMissing(Exception):
    """--dask without dask.distributed installed."""


def dask_outcomes(
    cases: Sequence[Case], address: str, timeout: float, coverage: bool = False
) -> Iterator[tuple[int, Outcome]]:
    """(index, outcome) of each case, in the order they finish, on a Dask cluster."""
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise DaskMissing() from None
    client = Client(address)
    futures = [client.submit(execute_subprocess, c, timeout, coverage, pure=False) for c in cases]
    index = {f.key: i for i, f in enumerate(futures)}
    try:
        for f in as_completed(futures):
            try:
                outcome = f.result()
            except Exception as exc:  # noqa: BLE001 — a worker lost or a task failed
                outcome = Outcome(None, "", "", 0.0, crashed=f"{type(exc).__name__}: {exc}")
            yield index[f.key], outcome
    finally:
        client.cancel(futures)
        client.close()
