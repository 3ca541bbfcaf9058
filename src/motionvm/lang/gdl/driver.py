"""GDL drivers: the scenario loop, and what `motionvm run|check|dump` call.

Exit codes of `main_run`: 0 ok; 1 a run-time error happened (the run went on);
2 compile errors (nothing ran); 3 a bad scenario file or --force argument.
Without an end time (`until`, from the caller or the scenario) a run ends once the
scenario has no events left, the ready queue is empty and every axis stands still or
runs at a constant commanded speed.
"""

from __future__ import annotations

from collections import deque
from typing import TextIO

from motionvm.lang.gdl.app import App, ProcInfo
from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.dump import dump_ast, dump_tokens
from motionvm.lang.gdl.lower import emit_python
from motionvm.lang.gdl.rts import DT_MS, Rts
from motionvm.lang.gdl.scenario import (
    Event,
    Scenario,
    ScenarioError,
    load_scenario,
    parse_target,
    parse_value,
)
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

EXIT_OK, EXIT_RUNTIME, EXIT_COMPILE, EXIT_SCENARIO = 0, 1, 2, 3


def _apply(rts: Rts, ev: Event) -> None:
    t = ev.target
    for e in t.elements:
        if ev.action == "set":
            rts.input(t.obj, t.spec.keyword, e, ev.value)
        elif ev.action == "force":
            rts.force(t.obj, t.spec.keyword, e, ev.value)
        else:
            rts.release(t.obj, t.spec.keyword, e)


def parse_forces(app: App, forces: list[str]) -> list[Event]:
    """`--force "VALUE OF fan = 300"` arguments as force events at t=0."""
    out: list[Event] = []
    for i, text in enumerate(forces):
        ref, sep, raw = text.partition("=")
        try:
            if not sep:
                raise ValueError("write --force 'KEYWORD OF object = value'")
            target = parse_target(app, ref.strip())
            if not target.spec.forceable:
                raise ValueError(
                    f"{target.spec.keyword} of {target.obj.type.name} cannot be "
                    f"forced (access {target.spec.access})"
                )
            value = parse_value(target, raw.strip())
        except ValueError as exc:
            raise ScenarioError(f"--force '{text}': {exc}") from None
        out.append(Event(-1 - i, 0, "force", target, value, None, None))
    return out


def run_scenario(
    rts: Rts,
    scenario: Scenario,
    until: float | None,
    forces: list[Event] | None = None,
    *,
    jump: bool = True,
) -> None:
    """Drive `rts` through the scenario (see the module docstring for when it ends).

    `jump=False` steps every cycle even when nothing moves (tests compare the two).
    """
    end = until if until is not None else scenario.until
    end_cycle = None if end is None else max(0, round(end * 1000 / DT_MS))
    for target, value in scenario.initial:
        for e in target.elements:
            rts.init_value(target.obj, target.spec.keyword, e, value)
    timed = deque(ev for ev in scenario.events if ev.during is None)
    rts.injections = [ev for ev in scenario.events if ev.during is not None]

    def inject(proc: ProcInfo, line: int) -> None:
        for ev in list(rts.injections):
            assert isinstance(ev, Event)
            if ev.cycle <= rts.cycle and ev.during == proc.name and ev.line == line:
                rts.injections.remove(ev)
                _apply(rts, ev)

    rts.apply_injection = inject
    for ev in forces or []:
        _apply(rts, ev)
        rts.drain()
    while True:
        rts.runs_this_cycle = 0
        if rts.cycle > 0:
            rts.step_devices()
        while timed and timed[0].cycle <= rts.cycle:
            _apply(rts, timed.popleft())
            rts.drain()
        if end_cycle is not None:
            if rts.cycle >= end_cycle:
                break
        elif not timed and not rts.transient:
            break
        if rts.moving or not jump:
            rts.cycle += 1
        else:
            nxt = [c for c in (timed[0].cycle if timed else None, end_cycle) if c is not None]
            rts.cycle = max(rts.cycle + 1, min(nxt))
    for ev in rts.injections:
        assert isinstance(ev, Event)
        rts.err.write(
            f"warning: scenario event {ev.number} (during {ev.during}, line "
            f"{ev.line}) was never applied\n"
        )


def run_app(
    app: App,
    scenario_path: str | None,
    until: float | None,
    out: TextIO,
    err: TextIO | None = None,
    forces: list[str] | None = None,
    shuffle_seed: int | None = None,
) -> int:
    """Run `app` against a scenario file (or none); output on `out`, errors on `err`.

    `forces` are `--force 'REF = VALUE'` texts applied at t=0; `shuffle_seed` permutes the
    order of procedures sharing an activator (see `Rts`). Returns 0, 1 (a run-time error
    happened) or 3 (bad scenario or --force).
    """
    err = err if err is not None else out
    try:
        scenario = (
            load_scenario(scenario_path, app)
            if scenario_path is not None
            else Scenario((), (), None)
        )
        force_events = parse_forces(app, forces or [])
    except ScenarioError as exc:
        err.write(f"error: {exc}\n")
        return EXIT_SCENARIO
    rts = Rts(app, out, err, shuffle_seed=shuffle_seed)
    run_scenario(rts, scenario, until, force_events)
    return EXIT_RUNTIME if rts.error_count else EXIT_OK


def _compile(paths: list[str], stderr: TextIO) -> App | None:
    """Compile, printing every diagnostic sorted by file (as given), line and column."""
    sink = DiagnosticSink()
    app = compile_app(paths, sink=sink)
    order = {p: i for i, p in enumerate(paths)}
    items = sorted(sink.items, key=lambda d: (order.get(d.pos.file, -1), d.pos.line, d.pos.col))
    stderr.writelines(render_diagnostic(d) + "\n" for d in items)
    return app


def main_check(paths: list[str], stdout: TextIO, stderr: TextIO) -> int:
    """`motionvm check FILE.gdl...`: 0 when the application compiles, else 2."""
    return EXIT_OK if _compile(paths, stderr) is not None else EXIT_COMPILE


def main_run(
    paths: list[str],
    scenario: str | None,
    until: float | None,
    stdout: TextIO,
    stderr: TextIO,
    forces: list[str] | None = None,
    shuffle_seed: int | None = None,
) -> int:
    """`motionvm run FILE.gdl... [--scenario S.toml] [--until S] [--force 'REF = V']...`.

    `shuffle_seed` (a `--shuffle-order SEED` option) permutes the order of procedures
    sharing an activator, to test that a program does not depend on it.
    """
    app = _compile(paths, stderr)
    if app is None:
        return EXIT_COMPILE
    return run_app(app, scenario, until, stdout, stderr, forces, shuffle_seed)


def main_dump(paths: list[str], stage: str, stdout: TextIO, stderr: TextIO) -> int:
    """`motionvm dump --stage tokens|ast|py FILE...`: 0, 2 on errors, 3 on a bad stage."""
    if stage not in ("tokens", "ast", "py"):
        stderr.write(f"error: unknown stage '{stage}' (tokens, ast, py)\n")
        return EXIT_SCENARIO
    if stage == "py":
        app = _compile(paths, stderr)
        if app is None:
            return EXIT_COMPILE
        stdout.write(emit_python(app))
        return EXIT_OK
    sink = DiagnosticSink()
    for path in paths:
        try:
            stdout.write((dump_tokens if stage == "tokens" else dump_ast)(path, sink))
        except OSError as exc:
            stderr.write(f"error: cannot read {path}: {exc.strerror or exc}\n")
            return EXIT_COMPILE
    stderr.writelines(render_diagnostic(d) + "\n" for d in sink.items)
    return EXIT_COMPILE if sink.has_errors else EXIT_OK
