"""`motionvm run|check x.pdl`: the PDL halves of the command line (wired by motionvm/cli.py).

    main_check(paths, stdout, stderr) -> 0 ok | 2 compile errors | 3 bad command line
    main_run(paths, start_label, until, stdout, stderr)
                                      -> 0 ok | 1 a task faulted | 2 | 3

Diagnostics go to stderr as `FILE:LINE:COL: error: MESSAGE`, the source line and a
caret, sorted by file, line and column. A run simulates one drive: the `#task/n`
tasks start at reset, then each `--start _label` (host run, in the order given;
`top` runs the program from its first statement on the lowest idle task). Every
printl message is one line on stdout; a runtime fault is
`FILE:LINE: runtime error in task N: MESSAGE` on stderr. The run ends when every task
has ended and the axis rests, or at `until` seconds of simulated time.
"""

from __future__ import annotations

import os
from typing import TextIO

from motionvm.lang.pdl.drive_rt import Drive, DriveConfig, Message
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
    """Compile one PDL program, run it on a simulated drive, print its messages.

    `stamp` prefixes each message with `[t=SECONDS][task N] ` (simulated time).
    `scope` (a `sim.scope.ScopeRequest`, from --scope/--scope-out/--scope-every)
    records the drive's channels once per 1 ms (15 phases), see `_run_scoped`.
    """
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
    programs, code = _compile(paths, stderr)
    if code:
        return code
    program = programs[0]
    for label in labels:
        if label != "top" and label not in program.entries:
            print(f"motionvm: --start {label}: the program has no label '{label}'", file=stderr)
            return EXIT_USAGE

    rate = (config or DriveConfig()).phase_rate

    def show(m: Message) -> None:
        prefix = f"[t={m.phase / rate:.6f}][task {m.task}] " if stamp else ""
        print(prefix + m.text, file=stdout)

    def fault(text: str) -> None:
        print(text, file=stderr)

    drive = Drive(program, config, on_message=show, on_fault=fault)
    for label in labels:
        try:
            if label == "top":
                free = next((t.id for t in drive.tasks if t.gen is None), None)
                if free is None:
                    raise ValueError("refused: all 4 tasks are busy")
                drive.start_top(free)
            else:
                drive.start(label)
        except ValueError as e:
            print(f"motionvm: --start {label}: {e}", file=stderr)
            return EXIT_USAGE
    if not drive.busy:
        print(
            f"{program.path}: note: no task runs: the program has no '#task/n;' and no "
            "--start label was given",
            file=stderr,
        )
    if scope is None:
        drive.run(until)
    elif not _run_scoped(drive, program, until, scope, stderr):
        return EXIT_USAGE
    return EXIT_FAULT if drive.faults else EXIT_OK


SCOPE_CYCLE = 0.001
"""A standalone drive's scope samples once per controller-cycle equivalent [s]."""


def _run_scoped(drive: Drive, program: PdlProgram, until: float | None, scope, stderr) -> bool:
    """`drive.run(until)` in 1 ms slices (15 phases at 15 kHz), sampling after each.

    Sample k shows the drive at the end of slice k (phase 15 * (k + 1)) and is stamped
    k * 1 ms, as a machine run's samples of cycle k are; the last slice may be shorter
    (`until`, or the drive going idle). Channels: `drive0.<name>` or just `<name>`.
    False (message on stderr) for an unknown channel or an unwritable output.
    """
    from motionvm.sim.scope import ChannelRegistry, ScopeError, ScopeRecorder
    from motionvm.sim.scope_sources import PdlDriveSource

    rate = drive.config.phase_rate
    per = max(1, round(SCOPE_CYCLE * rate))
    try:
        channels = ChannelRegistry([PdlDriveSource({0: drive}, bare=0)]).resolve_all(scope.channels)
    except ScopeError as exc:
        print(f"motionvm: error: {exc}", file=stderr)
        return False
    recorder = ScopeRecorder(channels, per / rate, scope.every)
    limit = None if until is None else round(until * rate)
    cycle = 0
    try:
        while True:
            count = per if limit is None else min(per, max(0, limit - drive.phase))
            done = drive.run_phases(count)
            recorder.sample(cycle)
            cycle += 1
            if done or (limit is not None and drive.phase >= limit):
                break
    except KeyboardInterrupt:  # keep what was recorded up to the interrupt
        _save_scope(recorder, scope, program.path, stderr)
        raise
    return _save_scope(recorder, scope, program.path, stderr)


def _save_scope(recorder, scope, title: str, stderr) -> bool:
    from motionvm.sim.scope import ScopeError

    for path in scope.outputs:
        try:
            recorder.save(path, title=title)
        except ScopeError as exc:
            print(f"motionvm: error: {exc}", file=stderr)
            return False
    return True
