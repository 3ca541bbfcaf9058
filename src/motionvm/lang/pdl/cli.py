"""`motionvm run|check x.pdl`: the PDL halves of the command line (wired by motionvm/cli.py).

    main_check(paths, stdout, stderr) -> 0 ok | 2 compile errors | 3 bad command line
    main_run(paths, start_label, until, stdout, stderr)
                                      -> 0 ok | 1 a task faulted | 2 | 3

Diagnostics go to stderr as `FILE:LINE:COL: error: MESSAGE`, the source line and a
caret, sorted by file, line and column. A run is the default machine with the program
on the drive of axis 0, a `machine_drives.PdlDrives` client in standalone mode on the
controller's clock: the `#task/n` tasks start at reset, then each `--start _label`
(host run, in the order given; `top` runs the program from its first statement on the
lowest idle task). Every printl message is one line on stdout; a runtime fault is
`FILE:LINE: runtime error in task N: MESSAGE` on stderr. The run ends when every task
has ended and the axis rests, or at `until` seconds of simulated time (to the phase).
"""

from __future__ import annotations

import os
from typing import TextIO

from motionvm.lang.pdl.drive_rt import DriveConfig
from motionvm.lang.pdl.lower import PdlProgram
from motionvm.lang.pdl.program import compile_pdl
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

EXIT_OK, EXIT_FAULT, EXIT_COMPILE, EXIT_USAGE = 0, 1, 2, 3


def _compile(paths: list[str], stderr: TextIO) -> tuple[list[PdlProgram], int]:
    sink = DiagnosticSink()
    programs: list[PdlProgram] = []
    for path in paths:
        program = compile_pdl(path, sink=sink)
        if program is not None:
            programs.append(program)
    for d in sorted(sink.items, key=lambda d: (d.pos.file, d.pos.line, d.pos.col)):
        print(render_diagnostic(d), file=stderr)
    return programs, (EXIT_COMPILE if sink.has_errors else EXIT_OK)


def _usage(paths: list[str], stderr: TextIO) -> bool:
    if not paths:
        print("motionvm: no PDL file given", file=stderr)
        return False
    for p in paths:
        if not p.lower().endswith(".pdl"):
            print(f"motionvm: '{p}' is not a .pdl file", file=stderr)
            return False
        if not os.path.isfile(p):
            print(f"motionvm: cannot read '{p}': no such file", file=stderr)
            return False
    return True


def main_check(paths: list[str], stdout: TextIO, stderr: TextIO) -> int:
    """Compile only; diagnostics on stderr; 0 if clean, 2 on errors, 3 on a bad command line."""
    if not _usage(paths, stderr):
        return EXIT_USAGE
    _, code = _compile(paths, stderr)
    return code


def main_run(
    paths: list[str],
    start_label: str | list[str] | None,
    until: float | None,
    stdout: TextIO,
    stderr: TextIO,
    config: DriveConfig | None = None,
    stamp: bool = False,
    scope=None,
) -> int:
    """Compile one PDL program, run it on the drive of axis 0 of the default machine,
    print its messages.

    `stamp` prefixes each message with `[t=SECONDS][task N] ` (simulated time).
    `scope` (a `sim.scope.ScopeRequest`, from --scope/--scope-out/--scope-every)
    records the drive's channels, `drive0.<name>` or just `<name>`, once per 1 ms
    controller cycle: the sample of cycle k shows the drive after phase 15 (k + 1), the
    last one the drive when it is found idle or at `until`.
    """
    from motionvm.lang.pdl.machine_drives import PdlDrives, PdlStartError, compile_program
    from motionvm.sim.controller import Controller
    from motionvm.sim.machine import DEFAULT_MACHINE

    if not _usage(paths, stderr):
        return EXIT_USAGE
    if len(paths) != 1:
        print(
            "motionvm: one .pdl program per drive; a machine file puts programs on several drives",
            file=stderr,
        )
        return EXIT_USAGE
    if until is not None and not until >= 0:
        print(f"motionvm: --until {until} must be a time >= 0 [s]", file=stderr)
        return EXIT_USAGE
    labels = [start_label] if isinstance(start_label, str) else list(start_label or [])

    def emit(line: str) -> None:
        print(line, file=stdout)

    def report(line: str) -> None:
        print(line, file=stderr)

    machine = DEFAULT_MACHINE
    try:
        drives = compile_program(paths[0], labels, report)
        if drives is None:
            return EXIT_COMPILE
        controller = Controller(machine.cycle_time, machine)
        client = PdlDrives(
            controller,
            drives,
            machine,
            emit=emit,
            report=report,
            stamp=stamp,
            standalone=True,
            config=config,
            until=until,
        )
        controller.add_client(client)
        client.boot()
    except PdlStartError as exc:
        report(str(exc))
        return EXIT_USAGE
    recorder = None
    if scope is not None:
        recorder = _scope_start(controller, client, scope, stderr)
        if recorder is None:
            return EXIT_USAGE
    try:
        controller.run()  # the client ends the drive at `until`, to the phase
    except KeyboardInterrupt:  # keep what was recorded up to the interrupt
        if recorder is not None:
            _save_scope(recorder, scope, drives[0].program.path, stderr)
        raise
    if recorder is not None and not _save_scope(recorder, scope, drives[0].program.path, stderr):
        return EXIT_USAGE
    return EXIT_FAULT if client.faults else EXIT_OK


def _scope_start(controller, client, scope, stderr):
    """A recorder of the requested channels on `controller`; None (message on stderr) for
    an unknown channel."""
    from motionvm.sim.scope import ChannelRegistry, ScopeError, ScopeRecorder

    try:
        channels = ChannelRegistry(client.scope_sources()).resolve_all(scope.channels)
    except ScopeError as exc:
        print(f"motionvm: error: {exc}", file=stderr)
        return None
    recorder = ScopeRecorder(channels, controller.cycle_time, scope.every)
    recorder.attach(controller)
    return recorder


def _save_scope(recorder, scope, title: str, stderr) -> bool:
    from motionvm.sim.scope import ScopeError

    for path in scope.outputs:
        try:
            recorder.save(path, title=title)
        except ScopeError as exc:
            print(f"motionvm: error: {exc}", file=stderr)
            return False
    return True
