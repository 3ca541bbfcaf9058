"""`motionvm run|check|compile|dump` for HMPL programs: task assignment, diagnostics, the run."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from motionvm.cli import EXIT_COMPILE, EXIT_OK, EXIT_RUNTIME, EXIT_USAGE, UsageError
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic


def assign_tasks(files: list[str], task_opts: list[str]) -> list[tuple[int, str]]:
    """Positional files take tasks 0, 1, 2, ... skipping ids given with --task N=FILE."""
    placed: dict[int, str] = {}
    for opt in task_opts:
        num, eq, path = opt.partition("=")
        if not eq or not num.strip().isdigit() or not path:
            raise UsageError(f"--task expects N=FILE, got '{opt}'")
        tid = int(num)
        if not 0 <= tid < 64:
            raise UsageError(f"--task {tid}: task ids are 0..63")
        if tid in placed:
            raise UsageError(f"task {tid} given twice ({placed[tid]} and {path})")
        placed[tid] = path
    nxt = 0
    for f in files:
        while nxt in placed:
            nxt += 1
        if nxt >= 64:
            raise UsageError("more than 64 task files")
        placed[nxt] = f
        nxt += 1
    for path in placed.values():
        if not Path(path).is_file():
            raise UsageError(f"{path}: no such file")
        if Path(path).suffix.lower() != ".hmpl":
            raise UsageError(f"{path}: not an HMPL file")
    return sorted(placed.items())


def _compile(args):
    from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks

    tasks = assign_tasks(list(args.files), list(args.task))
    sink = DiagnosticSink()
    prog, mem = compile_tasks([TaskFile(t, p) for t, p in tasks], sink)
    for d in sink.items:
        print(render_diagnostic(d), file=sys.stderr)
    return prog, mem, sink


def hmpl_command(args) -> int:
    if args.cmd == "check":
        prog, _mem, _sink = _compile(args)
        return EXIT_OK if prog is not None else EXIT_COMPILE
    if args.cmd == "compile":
        prog, _mem, _sink = _compile(args)
        if prog is None:
            return EXIT_COMPILE
        if args.emit_python:
            sys.stdout.write(prog.python_source())
        return EXIT_OK
    return run(args)


def run(args) -> int:
    from motionvm.lang.hmpl.rtapi import HmplRuntime, data_dir_default
    from motionvm.sim.controller import Controller
    from motionvm.sim.machine import DEFAULT_MACHINE, MachineFileError, load_machine

    if args.until is not None and not args.until >= 0:
        raise UsageError(f"--until must be a non-negative number of seconds, got {args.until}")
    if args.machine:
        try:
            machine = load_machine(args.machine)
        except MachineFileError as exc:
            print(str(exc), file=sys.stderr)
            return EXIT_USAGE
    else:
        machine = DEFAULT_MACHINE
    if not args.files and not args.task and not machine.pdl_drives:
        raise UsageError("no input files (and the machine file puts no PDL program on a drive)")
    scope = _scope_request(args)
    prog, mem, _sink = _compile(args)
    drives = _compile_drives(machine)
    if isinstance(drives, int):
        return EXIT_USAGE
    if prog is None or drives is None:
        return EXIT_COMPILE
    out = sys.stdout

    def emit(line: str) -> None:
        try:
            out.write(line + "\n")
        except BrokenPipeError:  # the reader went away (`| head`): end the run quietly
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            ctl.stop_requested = True

    def report(line: str) -> None:
        out.flush()
        print(line, file=sys.stderr)

    ctl = Controller(machine.cycle_time, machine=machine)
    data_dir = machine.data_dir or data_dir_default(machine.path.parent if machine.path else None)
    rt = HmplRuntime(
        ctl, prog, mem, emit=emit, report=report, data_dir=data_dir, task_slice=machine.task_slice
    )
    rt.stamp = bool(args.stamp)
    ctl.clients.append(rt)
    pdl = None
    if drives:  # the machine's PDL drives (lang/pdl/machine_drives.py): after the motion step
        from motionvm.lang.pdl.machine_drives import PdlDrives

        pdl = PdlDrives(ctl, drives, machine, emit=emit, report=report, stamp=bool(args.stamp))
        ctl.add_client(pdl)
        pdl.boot()
    rt.boot()
    sources = pdl.scope_sources() if pdl is not None else []
    recorder = _scope_start(scope, ctl, rt, sources) if scope else None  # the last client
    try:
        ctl.run(args.until, realtime=bool(getattr(args, "realtime", False)))
    except KeyboardInterrupt:
        if recorder is not None:  # keep what was recorded up to the interrupt
            _scope_save(scope, recorder, args)
        raise
    try:
        out.flush()
    except BrokenPipeError:
        pass
    if recorder is not None:
        _scope_save(scope, recorder, args)
    return EXIT_RUNTIME if rt.faults or (pdl is not None and pdl.faults) else EXIT_OK


def _compile_drives(machine):
    """The machine's compiled PDL drives ([] if none); None after compile errors (reported),
    EXIT_USAGE after a bad `pdl_start` label (reported)."""
    if not machine.pdl_drives:
        return []
    from motionvm.lang.pdl.machine_drives import PdlStartError, compile_drives

    def report(line: str) -> None:
        print(line, file=sys.stderr)

    try:
        return compile_drives(machine, report)
    except PdlStartError as exc:
        report(str(exc))
        return EXIT_USAGE


# ---------------------------------------------------------------- --scope (README "Scope")


def _scope_request(args):
    from motionvm.sim.scope import ScopeError, ScopeRequest

    try:
        return ScopeRequest.from_options(
            getattr(args, "scope", []),
            getattr(args, "scope_out", []),
            getattr(args, "scope_every", None),
        )
    except ScopeError as exc:
        raise UsageError(str(exc)) from None


def _scope_start(scope, ctl, rt, sources=()):
    """Resolve the channels (unknown ones: exit 3, before anything runs) and attach a recorder;
    `sources` are the run sides' own channel sources (PDL drives), asked last."""
    from motionvm.sim.scope import ScopeError, ScopeRecorder
    from motionvm.sim.scope_sources import registry_for

    registry = registry_for(ctl, rt)
    for source in sources:
        registry.register(source)
    try:
        channels = registry.resolve_all(scope.channels)
    except ScopeError as exc:
        raise UsageError(str(exc)) from None
    recorder = ScopeRecorder(channels, ctl.cycle_time, scope.every)
    recorder.attach(ctl)
    return recorder


def _scope_save(scope, recorder, args) -> None:
    from motionvm.sim.scope import ScopeError

    title = " ".join(list(args.files) + list(args.task))
    if recorder.hmi_gated and not any(recorder.hmi_on):
        print(
            "motionvm: note: the program called SetHMIScope but the HMI scope was never on "
            "at the end of a recorded cycle: the scope recording is empty",
            file=sys.stderr,
        )
    for path in scope.outputs:
        try:
            recorder.save(path, title=title)
        except ScopeError as exc:
            raise UsageError(str(exc)) from None


def dump_stage(path: str, stage: str, task_id: int) -> int:
    from motionvm.lang.hmpl import dump
    from motionvm.lang.hmpl.parser import parse
    from motionvm.lang.hmpl.preprocess import preprocess

    if not Path(path).is_file():
        raise UsageError(f"{path}: no such file")
    sink = DiagnosticSink()
    if stage == "py":
        from argparse import Namespace

        ns = Namespace(files=[path], task=[], emit_python=True, cmd="compile")
        return hmpl_command(ns)
    toks = preprocess(path, task_id=task_id, sink=sink)
    if stage == "tokens":
        sys.stdout.write(dump.dump_tokens(toks) + "\n")
    else:
        tu = parse(toks, sink)
        sys.stdout.write(dump.dump_ast(tu) + "\n")
    for d in sink.items:
        print(render_diagnostic(d), file=sys.stderr)
    return EXIT_COMPILE if sink.has_errors else EXIT_OK
