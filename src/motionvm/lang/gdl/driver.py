"""What `motionvm run|check|dump` call for GDL files: compile, then run on a controller.

`run_app` assembles a run: a `Controller` (the built-in machine, 1 ms cycle), the
scenario, a `client.GdlApplication` on the controller's cycle. Exit codes of
`main_run`: 0 ok; 1 a run-time error happened (the run went on); 2 compile errors
(nothing ran); 3 a bad scenario file, --force argument or machine (too few axes).
Without an end time (`until`, from the caller or the scenario) a run ends once the
scenario has no events left, the ready queue is empty and every motor stands still or
runs at a constant commanded speed (client.py).
"""

from __future__ import annotations

from typing import TextIO

from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.client import GdlApplication
from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.dump import dump_ast, dump_tokens
from motionvm.lang.gdl.lower import emit_python
from motionvm.lang.gdl.motors import GdlMachineError
from motionvm.lang.gdl.scenario import Scenario, ScenarioError, load_scenario
from motionvm.sim.controller import Controller
from motionvm.source.diagnostics import DiagnosticSink, render_diagnostic

EXIT_OK, EXIT_RUNTIME, EXIT_COMPILE, EXIT_SCENARIO = 0, 1, 2, 3


def run_app(
    app: App,
    scenario_path: str | None,
    until: float | None,
    out: TextIO,
    err: TextIO | None = None,
    forces: list[str] | None = None,
    shuffle_seed: int | None = None,
    *,
    controller: Controller | None = None,
) -> int:
    """Run `app` against a scenario file (or none); output on `out`, errors on `err`.

    `forces` are `--force 'REF = VALUE'` texts applied at t=0; `shuffle_seed` permutes the
    order of procedures sharing an activator (see `Rts`); `controller` (default: a new
    one with the built-in machine) runs it. Returns 0, 1 (a run-time error happened) or
    3 (bad scenario, --force or machine).
    """
    err = err if err is not None else out
    controller = controller if controller is not None else Controller()
    try:
        scenario = (
            load_scenario(scenario_path, app)
            if scenario_path is not None
            else Scenario((), (), None)
        )
        client = GdlApplication(
            controller,
            app,
            scenario,
            emit=lambda line: out.write(line + "\n"),
            report=lambda line: err.write(line + "\n"),
            forces=forces or (),
            shuffle_seed=shuffle_seed,
        )
    except (ScenarioError, GdlMachineError) as exc:
        err.write(f"error: {exc}\n")
        return EXIT_SCENARIO
    controller.add_client(client)
    controller.run(client.run_until(until))
    client.finish()
    return EXIT_RUNTIME if client.error_count else EXIT_OK


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
