"""Where the cases of `motionvm test` run: a pool of worker processes, or a Dask cluster.

A local worker runs one case at a time in its own process, through the command line's
`main` with stdout and stderr captured, in the case's folder, with a fresh data folder
(MOTIONVM_DATA_DIR). Before it runs a case it imports the run path and the compilers
of the case's languages, and only then does the case's wall-clock time limit start: it
measures the case's own run, not a first import (over a second on a busy machine). A
case that exceeds its limit has its worker killed and replaced while cases remain, so a
program that never ends fails instead of hanging the suite. A worker that dies (the
out-of-memory killer's SIGKILL) is reported with the signal that killed it; a worker
whose runner is gone (killed, even by SIGKILL) ends itself within a second; a case's
captured output is bounded (`OUTPUT_LIMIT`): a flood ends the case and fails it.
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
import threading
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
_WAIT_MOST_S = 3600.0
"""Longest single wait for the workers [s]; a longer deadline (`--case-timeout 1e308`)
is waited for in several, as the system's wait overflows past about 24 days."""
_RUN_MODULES = ("motionvm.cli.run", "motionvm.session")
"""What every run imports."""
OUTPUT_LIMIT = 16 * 1024 * 1024
"""Characters of stdout and stderr together a case may print before it is stopped."""
_PARENT_POLL_S = 0.25
"""How often a worker checks that its runner is still there [s]."""
_PR_SET_PDEATHSIG = 1


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
    flooded: bool = False
    """The case printed more than OUTPUT_LIMIT characters and was stopped."""


class OutputFlood(SystemExit):
    """Raised by a case's captured output past OUTPUT_LIMIT: it ends the case's run (a
    SystemExit, so that no task fault handler takes it for the program's own error)."""


class _Bounded(io.StringIO):
    """A capture of a case's output sharing one budget with the case's other stream."""

    def __init__(self, budget: list[int]) -> None:
        super().__init__()
        self.budget = budget

    def write(self, text: str) -> int:
        left = self.budget[0]
        if len(text) > left:
            super().write(text[:left])
            self.budget[0] = 0
            raise OutputFlood(3)
        self.budget[0] = left - len(text)
        return super().write(text)


def flood_message(limit: int = OUTPUT_LIMIT) -> str:
    """Why a flooding case failed."""
    return (
        f"printed more than {limit // (1024 * 1024)} MB (stdout and stderr together, the "
        "limit of a case's captured output): stopped; is it printing in an endless loop?"
    )


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
    budget = [OUTPUT_LIMIT]
    out, err = _Bounded(budget), _Bounded(budget)
    flooded = False
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
        except OutputFlood:
            flooded = True
        finally:
            run_module.COVERAGE_SINK = None
            os.chdir(cwd)
            if data_env is None:
                os.environ.pop("MOTIONVM_DATA_DIR", None)
            else:
                os.environ["MOTIONVM_DATA_DIR"] = data_env
    if flooded:
        return Outcome(
            None, out.getvalue(), err.getvalue(), time.perf_counter() - start, flooded=True
        )
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
    """Run `case` as `python -m motionvm run ARGV` in a child process (Dask workers). The
    child ends itself if this process dies (MOTIONVM_PARENT_PID); its output goes to
    files, and past OUTPUT_LIMIT bytes it is killed and the case fails as flooded."""
    import motionvm

    env = dict(os.environ)
    src = str(Path(motionvm.__file__).resolve().parents[1])
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["MOTIONVM_PARENT_PID"] = str(os.getpid())
    start = time.perf_counter()
    codes: list[int] = []
    out, err = [], []
    merged: dict | None = {} if coverage else None
    with tempfile.TemporaryDirectory(prefix="motionvm-test-") as data:
        env["MOTIONVM_DATA_DIR"] = data
        cov_file = os.path.join(data, ".coverage.json")
        for n, argv in enumerate(runs(case)):
            if codes and codes[-1] != case.expect.exit_code:
                break
            if coverage and argv[0] == "run":
                argv = [argv[0], "--cov-report", f"json:{cov_file}", *argv[1:]]
            left = timeout - (time.perf_counter() - start)
            budget = OUTPUT_LIMIT - sum(map(len, out)) - sum(map(len, err))
            code, o, e, why = _child(argv, case.folder, env, data, n, left, budget)
            out.append(o)
            err.append(e)
            if why is not None:
                elapsed = time.perf_counter() - start
                return Outcome(None, "".join(out), "".join(err), elapsed,
                               timed_out=why == "timeout", flooded=why == "flood")  # fmt: skip
            codes.append(code)
            if merged is not None and os.path.exists(cov_file):
                from motionvm.cli.coverage import read_json
                from motionvm.lang.coverage import merge

                merge(merged, read_json(cov_file))
                os.unlink(cov_file)
    code = _combined(codes, case.expect.exit_code)
    return Outcome(code, "".join(out), "".join(err), time.perf_counter() - start, coverage=merged)


def _child(argv, cwd, env, folder, n, timeout, budget):
    """(exit code, stdout, stderr, None | 'timeout' | 'flood') of one `motionvm` child,
    its output in files of `folder`, checked every tenth of a second."""
    paths = [os.path.join(folder, f".run{n}.{name}") for name in ("out", "err")]
    with open(paths[0], "wb") as fo, open(paths[1], "wb") as fe:
        proc = subprocess.Popen(
            [sys.executable, "-m", "motionvm", *argv], cwd=cwd, env=env,
            stdin=subprocess.DEVNULL, stdout=fo, stderr=fe,
        )  # fmt: skip
        end = time.monotonic() + max(timeout, 0.001)
        why = None
        while True:
            try:
                proc.wait(timeout=0.1)
                break
            except subprocess.TimeoutExpired:
                pass
            if os.fstat(fo.fileno()).st_size + os.fstat(fe.fileno()).st_size > budget:
                why = "flood"
            elif time.monotonic() >= end:
                why = "timeout"
            if why is not None:
                proc.kill()
                proc.wait()
                break
        if why is None and os.fstat(fo.fileno()).st_size + os.fstat(fe.fileno()).st_size > budget:
            why = "flood"
    texts = []
    for path in paths:
        with open(path, "rb") as f:
            texts.append(f.read(max(budget, 0)).decode("utf-8", "replace"))
    return proc.returncode, texts[0], texts[1], why


def die_with(parent: int, by_signal: bool) -> None:
    """End this process when `parent` is gone: on Linux at once (the kernel sends SIGKILL,
    `by_signal`: the parent's main thread started us), and everywhere by a thread that
    watches for being re-parented."""
    if by_signal and sys.platform.startswith("linux"):
        import ctypes

        with contextlib.suppress(OSError, AttributeError):
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(_PARENT_POLL_S)
        os._exit(1)

    if os.getppid() != parent:  # gone before we watched
        os._exit(1)
    threading.Thread(target=watch, name="motionvm-parent-watch", daemon=True).start()


def _serve(conn: Connection, parent: int = 0, by_signal: bool = False) -> None:
    """A worker process: for each case it receives, import what the case needs, say it
    runs, run it and send back its Outcome; None ends it. It ends itself when `parent`
    (its runner) is gone."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    if parent:
        die_with(parent, by_signal)
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
        by_signal = threading.current_thread() is threading.main_thread()
        self.process = ctx.Process(target=_serve, args=(child, os.getpid(), by_signal), daemon=True)
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
            wait_s = min(wait_s, _WAIT_MOST_S)
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
                    index, lost = w.index, _lost(w, dead)
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


def _lost(w: _Worker, dead: bool) -> Outcome:
    """The outcome of the case of a worker that timed out or died (`dead`: its pipe or
    process said so; it may not have been reaped yet)."""
    elapsed = time.perf_counter() - w.started
    if not dead and w.process.is_alive():
        return Outcome(None, "", "", elapsed, timed_out=True)
    w.process.join(timeout=5)
    return Outcome(None, "", "", elapsed, crashed=death(w.process.exitcode))


def death(exitcode: int | None) -> str:
    """How a worker process ended, for the report: its exit code or the signal's name."""
    if exitcode is None:
        return "it closed its pipe and did not exit"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        hint = " (as the out-of-memory killer does)" if name == "SIGKILL" else ""
        return f"killed by {name}{hint}"
    return f"worker exit code {exitcode}"


class DaskMissing(Exception):
    """--dask without dask.distributed installed."""


def batches(count: int, slots: int) -> list[range]:
    """Cases 0..count-1 cut into consecutive batches, one Dask task each: about four
    batches per slot of the cluster (a thread of a worker), so that a task's start-up and
    its round trip are paid per batch while a slow batch cannot hold back the end of the
    run for long."""
    size = max(1, -(-count // (4 * max(1, slots))))
    return [range(i, min(i + size, count)) for i in range(0, count, size)]


def execute_batch(cases: Sequence[Case], timeout: float, coverage: bool = False) -> list:
    """`execute_subprocess` of each case of a batch, in turn (one Dask task)."""
    return [execute_subprocess(c, timeout, coverage) for c in cases]


def dask_outcomes(
    cases: Sequence[Case], address: str, timeout: float, coverage: bool = False
) -> Iterator[tuple[int, Outcome]]:
    """(index, outcome) of each case, batch by batch in the order the batches finish, on
    a Dask cluster (`batches`: several cases per task)."""
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise DaskMissing() from None
    client = Client(address)
    slots = sum(client.nthreads().values())
    parts = batches(len(cases), slots)
    futures = [
        client.submit(execute_batch, [cases[i] for i in part], timeout, coverage, pure=False)
        for part in parts
    ]
    part_of = {f.key: part for f, part in zip(futures, parts)}
    try:
        for f in as_completed(futures):
            part = part_of[f.key]
            try:
                outcomes = f.result()
            except Exception as exc:  # noqa: BLE001 — a worker lost or a task failed
                lost = Outcome(None, "", "", 0.0, crashed=f"{type(exc).__name__}: {exc}")
                outcomes = [lost] * len(part)
            yield from zip(part, outcomes)
    finally:
        client.cancel(futures)
        client.close()
