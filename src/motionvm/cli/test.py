"""`motionvm test [PATHS]`: run the programs that carry expectations, report like pytest.

Cases are found by `cli/cases.py`, run by `cli/workers.py` (a process pool, or a Dask
cluster with `--dask`), judged by `cli/judge.py` and reported by `cli/report.py`. The
report is the same whatever the scheduling: cases are sorted by path and their results
printed in that order. Exit codes (pytest's): 0 every case passed (or, if `pending:`,
failed), 1 some failed, 3 bad usage, 5 no case was collected.
"""

from __future__ import annotations

import os
import sys
import time

from motionvm.cli.cases import Case, CollectError, collect
from motionvm.cli.exits import EXIT_OK, EXIT_RUNTIME, UsageError
from motionvm.cli.judge import ERROR, FAILED, Verdict, judge
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
    cases = select(found, args.k)
    from motionvm.cli.coverage import parse_reports

    cov_reports = parse_reports(args.cov_report)
    verbosity = args.verbose - args.quiet
    report = TextReport(sys.stdout, verbosity)
    where = f" on the Dask cluster at {args.dask}" if args.dask else ""
    report.start(len(cases), len(found) - len(cases), where)
    if not cases:
        print("no cases ran" if found else "no cases found", file=sys.stdout)
        return EXIT_NO_CASES
    start = time.perf_counter()
    coverage: dict | None = {} if cov_reports else None
    verdicts, stopped = _run(cases, args, jobs, report, coverage)
    wall_time = time.perf_counter() - start
    report.finish(verdicts, wall_time, stopped)
    if args.junitxml:
        try:
            write_junit(args.junitxml, verdicts, wall_time)
        except (OSError, ValueError) as exc:  # unreachable, or not an address
            raise UsageError(f"--junitxml {args.junitxml}: {exc.strerror or exc}") from None
    if coverage is not None:
        from motionvm.cli.coverage import write_reports

        write_reports(cov_reports, coverage)
    return EXIT_RUNTIME if any(v.status in (FAILED, ERROR) for v in verdicts) else EXIT_OK


def _run(
    cases: list[Case], args, jobs: int, report: TextReport, coverage: dict | None = None
) -> tuple[list[Verdict], bool]:
    """Verdicts of the cases in order (a prefix with -x), and whether -x stopped the run.
    `coverage`: the cases' coverage is merged into it."""
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

    if flush():
        return verdicts, True
    timeout = args.case_timeout
    subset = [cases[i] for i in runnable]
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
            if coverage is not None and outcome.coverage:
                merge(coverage, outcome.coverage)
            i = runnable[k]
            done[i] = judge(cases[i], outcome, timeout)
            if flush():
                return verdicts, True
    finally:
        stream.close()
    return verdicts, False


def _chain(first, rest):
    if first is None:
        return
    yield first
    yield from rest
