"""`motionvm run | check | compile`: options -> a `session.RunSpec`, output -> the terminal."""

from __future__ import annotations

import os
import sys
import time

from motionvm.cli.colour import coloured
from motionvm.cli.colour import wanted as colour_wanted
from motionvm.cli.coverage import parse_reports
from motionvm.cli.exits import (
    EXIT_COMPILE,
    EXIT_INTERRUPTED,
    EXIT_OK,
    EXIT_RUNTIME,
    EXIT_TIMEOUT,
    UsageError,
)
from motionvm.cli.interrupts import (
    finishing_files,
    forget_unhandled_interrupt,
    terminate_as_exit,
)
from motionvm.cli.progress import RunProgress
from motionvm.cli.progress import wanted as progress_wanted
from motionvm.lang import LANGUAGES, LanguageInputError, language_of
from motionvm.runtime.waits import never_ends
from motionvm.session import (
    TIMEOUT,
    CompileFailed,
    RunSpec,
    Session,
    SessionError,
    Source,
    check,
)
from motionvm.sim.controller import FOREVER, UNTIL


def sources_of(args) -> list[Source]:
    """Positional files, then `--task N=FILE` placements (HMPL)."""
    out = [Source(f) for f in args.files]
    for opt in getattr(args, "task", []):
        num, eq, path = opt.partition("=")
        if not eq or not num.strip().isdigit() or not path:
            raise UsageError(f"--task expects N=FILE, got '{opt}'")
        lang = language_of(path)
        if lang is None or not lang.places_tasks:
            takers = " or ".join(x.name for x in LANGUAGES if x.places_tasks)
            raise UsageError(f"--task {opt}: {path} is not an {takers} file")
        out.append(Source(path, task=int(num)))
    return out


def _scope_request(args):
    """The checked --scope/--scope-out/--scope-every/--scope-window request (None if none)."""
    from motionvm.sim.scope import ScopeError, ScopeRequest

    try:
        return ScopeRequest.from_options(
            getattr(args, "scope", []),
            getattr(args, "scope_out", []),
            getattr(args, "scope_every", None),
            getattr(args, "scope_window", None),
        )
    except ScopeError as exc:
        raise UsageError(str(exc)) from None


def stdout_gone() -> None:
    """The reader of stdout went away (`| head`): point stdout at the null device, so the
    rest of the output, and the interpreter's last flush of what is still buffered,
    cannot fail again (Python would print 'Exception ignored ... BrokenPipeError' and
    exit with 120)."""
    try:
        fd = os.open(os.devnull, os.O_WRONLY)
    except OSError:
        return
    try:
        os.dup2(fd, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # a replaced or closed sys.stdout
        pass
    finally:
        os.close(fd)


def flush_stdout() -> None:
    """Flush stdout; a reader that went away is no error (see `stdout_gone`)."""
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        stdout_gone()


def _report(line: str) -> None:
    flush_stdout()
    print(coloured(line) if colour_wanted() else line, file=sys.stderr)


def cmd_check(args) -> int:
    spec = RunSpec(sources_of(args), werror=args.werror)
    try:
        return EXIT_OK if check(spec, _report) else EXIT_COMPILE
    except SessionError as exc:
        raise UsageError(str(exc), located=exc.located) from None


def cmd_compile(args) -> int:
    from motionvm.lang import CompileRequest
    from motionvm.session import WERROR_NOTE, check_sources
    from motionvm.sim.machine import DEFAULT_MACHINE
    from motionvm.source.diagnostics import in_order, render_diagnostic

    sources = sources_of(args)
    try:
        check_sources(sources)
    except SessionError as exc:
        raise UsageError(str(exc), located=exc.located) from None
    langs = {language_of(s.path) for s in sources}
    if len(langs) != 1 or not next(iter(langs)).places_tasks:
        raise UsageError(
            "'compile' supports HMPL files only (use 'motionvm dump --stage py' for PDL and GDL)"
        )
    (lang,) = langs
    try:
        result = lang.compile(sources, CompileRequest(DEFAULT_MACHINE))
    except LanguageInputError as exc:
        raise UsageError(str(exc), located=exc.located) from None
    for d in in_order(result.diagnostics):
        _report(render_diagnostic(d))
    if result.program is None:
        return EXIT_COMPILE
    if args.werror and any(d.severity == "warning" for d in result.diagnostics):
        _report(WERROR_NOTE)
        return EXIT_COMPILE
    if args.emit_python:
        sys.stdout.write(lang.python_source(result.program))
    return EXIT_OK


COVERAGE_SINK: list | None = None
"""Set by a worker of `motionvm test`: each run's coverage data is appended to it (and
the run counts coverage) instead of being written by `--cov-report`."""


def cmd_run(args) -> int:
    cov_reports = parse_reports(getattr(args, "cov_report", []))
    sources = sources_of(args)
    if not sources and not args.machine:
        raise UsageError("no input files")
    spec = RunSpec(
        sources,
        machine=args.machine,
        scenario=args.scenario,
        scope=_scope_request(args),
        stamp=bool(args.stamp),
        options={
            "starts": tuple(args.start),
            "forces": tuple(args.force),
            "shuffle_seed": args.shuffle_order,
        },
        skip=not args.no_skip,
        scope_title=" ".join(list(args.files) + list(args.task)),
        werror=args.werror,
        coverage=bool(cov_reports) or COVERAGE_SINK is not None,
    )
    sessions: list[Session] = []  # the session, once it exists
    gone = False  # stdout's reader went away

    def emit(line: str) -> None:
        nonlocal gone
        if not gone:
            try:  # sys.stdout as it is now: a progress bar may route it above itself
                sys.stdout.write(line + "\n")
                return
            except BrokenPipeError:  # the reader went away (`| head`): end the run quietly
                gone = True
                stdout_gone()
        # asked again at every later line: a stop asked before the run started (a
        # message printed while booting) would be forgotten when the run begins
        if sessions:
            sessions[0].controller.stop_requested = True

    with terminate_as_exit():
        return _run_session(spec, sources, args, emit, lambda s: sessions.append(s))


def _run_session(spec: RunSpec, sources, args, emit, started) -> int:
    """Assemble and run `spec`, write its scope files, print its verdict; the exit code.

    Ctrl-C at any moment after the session exists still writes the scope files with
    what was recorded (a sample cut short by the interrupt is left out), then exits 130;
    a Ctrl-C while they are written lets them finish (`finishing_files`)."""
    session: Session | None = None
    try:
        session = Session(spec, emit=emit, report=_report)
        started(session)
        if not sources and not session.has_programs:
            raise UsageError("no input files (and the machine file puts no PDL program on a drive)")
        wall_0 = time.perf_counter()  # for the summary line only; the run never reads it
        ends = [t for t in (args.until, args.timeout) if t is not None]
        bar = RunProgress(min(ends, default=None)) if progress_wanted(args.no_progress) else None
        result, interrupted = None, False
        try:
            try:
                result = session.run(
                    args.until, realtime=bool(args.realtime), timeout=args.timeout, progress=bar
                )
            finally:
                if bar is not None:
                    bar.close()
            wall = time.perf_counter() - wall_0
            flush_stdout()
        except KeyboardInterrupt:
            forget_unhandled_interrupt()
            interrupted = True
            _interrupted(session)
        try:
            with finishing_files("the scope files"):
                session.save_scope()
        except KeyboardInterrupt:
            forget_unhandled_interrupt()
            interrupted = True
        if interrupted:
            return EXIT_INTERRUPTED
    except CompileFailed:
        return EXIT_COMPILE
    except SessionError as exc:
        raise UsageError(str(exc), located=exc.located) from None
    finally:
        # free the run's memory now: a caller of `main` in a loop (a test suite) would
        # otherwise hold every run's program memory until a full garbage collection
        if session is not None:
            faults = session.fault_count
            _save_coverage(session, args)
            session.close()
    _verdict(result, args)
    if sys.stderr.isatty():
        _summary(result, wall, faults)
    if result.reason in (TIMEOUT, FOREVER):
        return EXIT_TIMEOUT
    return EXIT_RUNTIME if faults else EXIT_OK


def _save_coverage(session: Session, args) -> None:
    """The run's coverage: to the test worker's sink, or written as `--cov-report` asks."""
    if session.coverage is None:
        return
    data = session.coverage.data()
    if COVERAGE_SINK is not None:
        COVERAGE_SINK.append(data)
    reports = parse_reports(getattr(args, "cov_report", []))
    if reports:
        from motionvm.cli.coverage import write_reports

        write_reports(reports, data)


def cmd_scope(args) -> int:
    """`motionvm scope --list`: the channels a run of the files would offer, not run."""
    if not args.list:
        raise UsageError("scope: nothing to do; 'motionvm scope --list FILE...' lists the channels")
    spec = RunSpec(sources_of(args), machine=args.machine, scenario=args.scenario)
    try:
        session = Session(spec, emit=lambda line: None, report=_report)
        channels = session.scope_channels()
        session.close()
    except CompileFailed:
        return EXIT_COMPILE
    except SessionError as exc:
        raise UsageError(str(exc), located=exc.located) from None
    width = max((len(name) for name, _ in channels), default=0)
    for name, unit in channels:
        sys.stdout.write(f"{name:<{width}}  {unit}".rstrip() + "\n")
    return EXIT_OK


def _verdict(result, args) -> None:
    """The notes of a run that `--until` ended, the errors of one `--timeout` ended."""
    if result.reason == UNTIL:
        for w in result.still_running:
            _report(w.render("note", f"still ran when the run ended at t={result.end:g} s"))
    elif result.reason == TIMEOUT:
        for w in result.still_running:
            _report(w.render("error", f"had not finished after --timeout {args.timeout:g} s"))
        _report(
            f"motionvm: error: the run did not finish within --timeout {args.timeout:g} s of "
            "simulated time"
        )
    elif result.reason == FOREVER:
        for line in never_ends(result.still_running, result.sim_time):
            _report(line)


def _interrupted(session: Session) -> None:
    """Ctrl-C during a run: say so at once, with the simulated time it stopped at and the
    scope files still to write (the caller writes them: what was recorded up to the
    interrupt)."""
    request = session.spec.scope
    files = [str(p) for p in request.outputs if not request.is_stdout(p)] if request else []
    note = f", writing scope {', '.join(files)} ..." if files else ""
    _report(f"motionvm: interrupted at t={session.controller.sim_time:.3f} s{note}")
    sys.stderr.flush()


MEASURABLE_WALL = 0.01
"""Wall time [s] below which a run is too short for its speed to mean anything."""


def wall_text(wall: float) -> str:
    """A wall time with the precision it has: `1.23 s`, `45.6 ms`, `0.84 ms`."""
    if wall >= 1.0:
        return f"{wall:.2f} s"
    ms = wall * 1000.0
    return f"{ms:.1f} ms" if ms >= 1.0 else f"{ms:.2f} ms"


def _summary(result, wall: float, faults: int) -> None:
    """One line for a person at a terminal: simulated time, wall time, speed, faults. A
    run shorter than MEASURABLE_WALL gets no speed (its factor would be noise)."""
    speed = f" ({result.sim_time / wall:.0f}x real time)" if wall >= MEASURABLE_WALL else ""
    plural = "" if faults == 1 else "s"
    _report(
        f"motionvm: {result.sim_time:.3f} s simulated in {wall_text(wall)}{speed}, "
        f"{faults} fault{plural}"
    )
