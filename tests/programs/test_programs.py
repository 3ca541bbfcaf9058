"""The golden programs of every language: each case under tests/programs/ runs as
`motionvm test` runs it, and must do what its expectations say.

A case is a program file with expectations: inline directives in its comments (`expect:`,
`expect regex:`, `expect runtime error:`, `error:`, `warning:`, `diagnostics: exact`,
`check:`, `args:`, `task N:`, `restart:`, `pending:`) or an `X.out` file beside it. The
directives, the companion files (`X.taskK.hmpl`, `X.NAME.gdl`, `X.toml`,
`X.scenario.toml`) and how a case runs are documented in `motionvm.cli.cases`; the
cases are collected by its `collect`, run by `motionvm test`'s worker pool
(`motionvm.cli.workers`, one process per CPU, a wall-clock limit per case) and judged by
`motionvm.cli.judge`. A test's id is the program's path relative to tests/programs/.

The selected cases all run when the first of them is judged; the tests then report one
verdict each. `MOTIONVM_UPDATE_GOLDEN=1` rewrites the `X.out` files with what the
programs print (review the diff); inline expectations are never rewritten.
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import pytest

from motionvm.cli.cases import Case, collect
from motionvm.cli.judge import FAILED, PASSED, XFAILED, judge
from motionvm.cli.workers import Outcome, local_outcomes

PROGRAMS = Path(__file__).resolve().parent
CASES = collect([str(PROGRAMS)], base=PROGRAMS)
CASE_TIMEOUT_S = 60.0
"""Wall-clock limit of one case [s]."""


@pytest.fixture(scope="module")
def outcomes(request: pytest.FixtureRequest) -> dict[str, Outcome]:
    """What each selected case did, by id: all run at once on the worker pool."""
    selected = [
        item.callspec.params["case"]
        for item in request.session.items
        if getattr(item, "module", None) is request.module and hasattr(item, "callspec")
    ]
    runnable = [c for c in selected if c.problem is None]
    jobs = os.cpu_count() or 1
    done = dict(local_outcomes(runnable, jobs, CASE_TIMEOUT_S))
    return {runnable[i].id: outcome for i, outcome in done.items()}


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.id)
def test_program(case: Case, outcomes: dict[str, Outcome], golden) -> None:
    outcome = outcomes.get(case.id)
    exp = case.expect
    if golden.update and outcome is not None and exp.stdout_file and not outcome.timed_out:
        golden.write(Path(case.folder) / exp.stdout_file, outcome.stdout)
        case = dataclasses.replace(
            case, expect=dataclasses.replace(exp, stdout_text=outcome.stdout)
        )
    verdict = judge(case, outcome, CASE_TIMEOUT_S)
    if verdict.status == XFAILED:
        pytest.xfail(f"pending: {case.pending}")
    if verdict.status != PASSED:
        stderr = f"\n--- stderr ---\n{verdict.stderr.rstrip()}" if verdict.stderr.strip() else ""
        kind = "failed" if verdict.status == FAILED else "could not run"
        pytest.fail(f"{case.id} {kind}:\n{verdict.details}{stderr}", pytrace=False)


def test_every_language_has_golden_programs() -> None:
    suffixes = {Path(c.id).suffix for c in CASES}
    assert suffixes == {".hmpl", ".pdl", ".gdl"}
