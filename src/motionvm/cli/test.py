"""`motionvm test [PATHS]`: run the programs that carry expectations, report like pytest.

Cases are found by `cli/cases.py`, run by `cli/workers.py` (a process pool, or a Dask
cluster with `--dask`), judged by `cli/judge.py` and reported by `cli/report.py`. The
report is the same whatever the scheduling: cases are sorted by path and their results
printed in that order. Exit codes (pytest's): 0 every case passed (or, if `pending:`,
failed), 1 some failed, 3 bad usage, 5 no case was collected. Which cases failed
last is kept in `.motionvm_cache/` (cli/testcache.py) for `--lf`.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from pathlib import Path

from motionvm.cli.cases import Case, CollectError, collect
from motionvm.cli.exits import EXIT_OK, EXIT_RUNTIME, UsageError
from motionvm.cli.judge import ERROR, FAILED, PASSED, Verdict, judge
from motionvm.cli.keywords import KeywordError, compile_keywords
from motionvm.cli.report import TextReport, write_junit

EXIT_NO_CASES = 5
"""No case was collected (pytest's exit code for 'no tests ran')."""


def select(cases: list[Case], expr: str | None) -> list[Case]:
    """The cases whose id matches `-k EXPR` (cli/keywords.py: words, `and`, `or`, `not`,
    parentheses); UsageError for an expression that does not parse."""
    if not expr:
        return cases
    try:
        matches = compile_keywords(expr)
    except KeywordError as exc:
        raise UsageError(f"-k: cannot read '{expr}': {exc}") from None
    return [c for c in cases if matches(c.id)]


def cmd_test(args) -> int:
    jobs = args.jobs if args.jobs is not None else (os.cpu_count() or 1)
    if jobs < 1:
        raise UsageError(f"-j must be at least 1, got {jobs}")
    if not args.case_timeout > 0:
        raise UsageError(
            f"--case-timeout must be a positive number of seconds, got {args.case_timeout}"
        )
    try:
        found = collect(args.files or ["."])
    except CollectError as exc:
        raise UsageError(str(exc)) from None
    durations = getattr(args, "durations", None)
    if durations is not None and durations < 0:
        raise UsageError(f"--durations must be 0 (all) or more, got {durations}")
    if getattr(args, "repeat", 1) < 1:
        raise UsageError(f"--repeat must be at least 1, got {args.repeat}")
    if getattr(args, "cache_clear", False):
        from motionvm.cli import resultcache

        resultcache.clear()
    cases = select(found, args.k)
    verbosity = args.verbose - args.quiet
    if getattr(args, "last_failed", False):
        cases = _last_failed(cases, verbosity)
    if getattr(args, "collect_only", False):
        return _list(cases, len(found) - len(cases), verbosity)
    from motionvm.cli.coverage import parse_reports

    cov_reports = parse_reports(args.cov_report)
    report = TextReport(sys.stdout, verbosity)
    where = f" on the Dask cluster at {args.dask}" if args.dask else ""
    report.start(len(cases), len(found) - len(cases), where)
    if not cases:
        print("no cases ran" if found else "no cases found", file=sys.stdout)
        return EXIT_NO_CASES
    start = time.perf_counter()
    coverage: dict | None = {} if cov_reports else None
    updated: list[str] = []
    cached: list[int] = []
    verdicts, stopped = _run(cases, args, jobs, report, coverage, updated, cached)
    wall_time = time.perf_counter() - start
    report.finish(verdicts, wall_time, stopped, durations, len(cached))
    if updated:
        print(
            f"updated {len(updated)} .out file{'s' if len(updated) > 1 else ''}: "
            + ", ".join(updated)
        )
    from motionvm.cli.testcache import update_last_failed

    update_last_failed(
        (v.case.id for v in verdicts),
        (v.case.id for v in verdicts if v.status in (FAILED, ERROR)),
    )
    if args.junitxml:
        try:
            write_junit(args.junitxml, verdicts, wall_time)
        except (OSError, ValueError) as exc:  # unreachable, or not an address
            raise UsageError(f"--junitxml {args.junitxml}: {exc.strerror or exc}") from None
    if coverage is not None:
        from motionvm.cli.coverage import write_reports

        write_reports(cov_reports, coverage)
    return EXIT_RUNTIME if any(v.status in (FAILED, ERROR) for v in verdicts) else EXIT_OK


def _last_failed(cases: list[Case], verbosity: int) -> list[Case]:
    """`--lf`: the cases that failed last time, or all of them when none did."""
    from motionvm.cli.testcache import read_last_failed

    failed = read_last_failed()
    chosen = [c for c in cases if c.id in failed]
    if verbosity >= 0:
        if chosen:
            noun = "failure" if len(chosen) == 1 else "failures"
            print(f"run-last-failure: rerun previous {len(chosen)} {noun}")
        else:
            print("run-last-failure: no previously failed cases, running all")
    return chosen or cases


def _list(cases: list[Case], n_deselected: int, verbosity: int) -> int:
    """`--collect-only`: the ids of the cases that would run, one a line."""
    for c in cases:
        print(c.id if c.problem is None or verbosity < 1 else f"{c.id} (error: {c.problem})")
    more = f" ({n_deselected} deselected)" if n_deselected else ""
    noun = "case" if len(cases) == 1 else "cases"
    if verbosity >= 0:
        print(f"\n{len(cases)} {noun} collected{more}")
    return EXIT_OK if cases else EXIT_NO_CASES


def _updated(case: Case, outcome, verdict: Verdict, timeout: float, updated: list[str]) -> Verdict:
    """`--update`: when only its stdout kept a case with an `X.out` file from passing,
    rewrite that file with the actual stdout; the case then passes."""
    exp = case.expect
    if (
        verdict.status != FAILED
        or exp.stdout_file is None
        or case.pending is not None
        or outcome.timed_out
        or outcome.crashed
        or outcome.flooded
    ):
        return verdict
    renewed = dataclasses.replace(case, expect=dataclasses.replace(exp, stdout_text=outcome.stdout))
    again = judge(renewed, outcome, timeout)
    if again.status != PASSED:
        return verdict
    path = Path(case.folder) / exp.stdout_file
    try:
        with open(path, "w", encoding="utf-8", newline="") as f:
            f.write(outcome.stdout)
    except OSError as exc:
        return dataclasses.replace(
            verdict, details=f"{verdict.details}\n--update: cannot write {path}: {exc.strerror}"
        )
    updated.append(str(Path(case.id).with_suffix(".out").as_posix()))
    return again


def _run(
    cases: list[Case],
    args,
    jobs: int,
    report: TextReport,
    coverage: dict | None = None,
    updated: list[str] | None = None,
    cached: list[int] | None = None,
) -> tuple[list[Verdict], bool]:
    """Verdicts of the cases in order (a prefix with -x), and whether -x stopped the run.
    `coverage`: the cases' coverage is merged into it; `updated`: with --update, the
    `.out` files rewritten are added to it; `cached`: the indices of the cases judged
    from the results cache (cli/resultcache.py; not with coverage, which it does not
    keep)."""
    from motionvm.cli import workers
    from motionvm.lang.coverage import merge

    runnable = [i for i, c in enumerate(cases) if c.problem is None]
    done: dict[int, Verdict] = {i: judge(c, None, 0) for i, c in enumerate(cases) if c.problem}
    verdicts: list[Verdict] = []

    def flush() -> bool:
        """Report the verdicts that are next in order; True: -x says stop."""
        while len(verdicts) in done:
            v = done.pop(len(verdicts))
            verdicts.append(v)
            report.progress(v)
            if args.exitfirst and v.status in (FAILED, ERROR):
                return True
        return False

    timeout = args.case_timeout
    keys: dict[int, str] = {}
    repeat = max(1, getattr(args, "repeat", None) or 1)
    runs_of: dict[int, list] = {}
    if coverage is None and cached is not None and repeat == 1:
        from motionvm.cli import resultcache

        memo: dict = {}
        for i in list(runnable):
            key = resultcache.case_key(cases[i], memo)
            if key is None:
                continue
            keys[i] = key
            stored = resultcache.load(key)
            if stored is not None:
                cached.append(i)
                runnable.remove(i)
                done[i] = _judged(cases[i], stored, timeout, args, updated)
    if flush():
        return verdicts, True
    subset = [cases[i] for i in runnable for _ in range(repeat)]
    if args.dask:
        try:
            outcomes = workers.dask_outcomes(subset, args.dask, timeout, coverage is not None)
            first = next(outcomes, None)
        except workers.DaskMissing:
            raise UsageError(
                "--dask needs dask.distributed: pip install 'motionvm[cluster]'"
            ) from None
        except (OSError, ValueError) as exc:  # unreachable, or not an address
            raise UsageError(f"--dask {args.dask}: cannot reach the scheduler: {exc}") from None
        stream = _chain(first, outcomes)
    else:
        stream = workers.local_outcomes(subset, jobs, timeout, coverage is not None)
    try:
        for k, outcome in stream:
            i = runnable[k // repeat]
            got = runs_of.setdefault(i, [])
            got.append(outcome)
            if coverage is not None and outcome.coverage and len(got) == 1:
                merge(coverage, outcome.coverage)
            if len(got) < repeat:
                continue
            del runs_of[i]
            if i in keys:
                from motionvm.cli import resultcache

                resultcache.store(keys[i], outcome)
            differs = _differing(cases[i], got)
            if differs is not None:
                done[i] = differs
            else:
                done[i] = _judged(cases[i], got[0], timeout, args, updated)
            if flush():
                return verdicts, True
    finally:
        stream.close()
    return verdicts, False


def _differing(case: Case, outcomes: list) -> Verdict | None:
    """`--repeat`: a failed verdict when the finished runs of a case did not all print
    and exit alike (a determinism bug, never retried); None when they did. A run that
    did not finish (timed out, killed, flooded) is judged as it is."""
    import difflib

    from motionvm.cli.judge import command_line

    unfinished = next(
        (o for o in outcomes if o.timed_out or o.crashed is not None or o.flooded), None
    )
    if unfinished is not None:
        return None if unfinished is outcomes[0] else _differing(case, [unfinished])
    first = outcomes[0]
    for n, other in enumerate(outcomes[1:], start=2):
        if (other.returncode, other.stdout, other.stderr) == (
            first.returncode, first.stdout, first.stderr
        ):  # fmt: skip
            continue
        lines = [command_line(case), f"run {n} of {len(outcomes)} differs from run 1 "
                 "(--repeat: the program is not deterministic)"]  # fmt: skip
        if other.returncode != first.returncode:
            lines.append(f"exit code {other.returncode}, run 1: {first.returncode}")
        for name, a, b in (("stdout", first.stdout, other.stdout),
                           ("stderr", first.stderr, other.stderr)):  # fmt: skip
            if a != b:
                diff = difflib.unified_diff(
                    a.splitlines(), b.splitlines(), f"{name} of run 1", f"{name} of run {n}",
                    lineterm="",
                )  # fmt: skip
                lines.append("\n".join(diff))
        return Verdict(case, FAILED, "\n".join(lines), first.wall_time, first.stdout, first.stderr)
    return None


def _judged(case: Case, outcome, timeout: float, args, updated: list[str] | None) -> Verdict:
    verdict = judge(case, outcome, timeout)
    if getattr(args, "update", False) and updated is not None:
        verdict = _updated(case, outcome, verdict, timeout, updated)
    return verdict


def _chain(first, rest):
    if first is None:
        return
    yield first
    yield from rest
