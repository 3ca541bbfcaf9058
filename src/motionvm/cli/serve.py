"""`motionvm serve`: a run paced to the wall clock with the controller's TCP servers.

The bound ports are printed on stderr as the servers start (`native-ascii listening on
127.0.0.1:3999`, then `user-ascii ...` and `modbus ...`); program messages go to stdout,
one flushed line each. The run goes on after every task has ended, until `--until` or
Ctrl-C, both normal ends (exit 0; 1 if a task stopped with a runtime error).
"""

from __future__ import annotations

import sys

from motionvm.cli.exits import EXIT_COMPILE, EXIT_OK, EXIT_RUNTIME, UsageError
from motionvm.cli.run import flush_stdout, sources_of, stdout_gone
from motionvm.session import CompileFailed, RunSpec, Session, SessionError


def _report(line: str) -> None:
    flush_stdout()
    print(line, file=sys.stderr, flush=True)


def cmd_serve(args) -> int:
    sources = sources_of(args)
    if not sources and not args.machine:
        raise UsageError("no input files")
    spec = RunSpec(sources, machine=args.machine, stamp=bool(args.stamp), werror=bool(args.werror))
    gone = False

    def emit(line: str) -> None:
        nonlocal gone
        if gone:
            return
        try:
            sys.stdout.write(line + "\n")
            sys.stdout.flush()
        except BrokenPipeError:  # the reader went away; the servers go on
            gone = True
            stdout_gone()

    def ready(ports: dict[str, int]) -> None:
        bind = session.machine.comm.bind
        for name, port in ports.items():
            _report(f"{name} listening on {bind}:{port}")

    try:
        session = Session(spec, emit=emit, report=_report)
        try:
            session.serve(args.until, ready=ready)
        except KeyboardInterrupt:
            _report("motionvm: serve: stopped (Ctrl-C)")
    except CompileFailed:
        return EXIT_COMPILE
    except SessionError as exc:
        raise UsageError(str(exc), located=exc.located) from None
    flush_stdout()
    faults = session.fault_count
    session.close()  # free the run's memory now (see cmd_run)
    return EXIT_RUNTIME if faults else EXIT_OK
