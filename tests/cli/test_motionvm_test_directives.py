"""`motionvm test`'s directives beyond stdout lines: warnings, exact diagnostics, compile-only
cases, runtime errors in order, a restart of the controller, pending cases, and a
misspelt directive."""

from __future__ import annotations

import contextlib
import io
import os
from pathlib import Path

from motionvm.cli import main
from motionvm.cli.cases import collect

UNUSED = 'void main() {\n    int unused;\n    Print("hi");\n}\n'
"""An HMPL program with one warning, at 2:9: unused variable 'unused'."""
TWO_FAULTS = (
    'void main() {\n    int z = 0;\n    Print("a");\n    StartTask(1);\n    Sleep(10);\n'
    '    Print("%d", 1 / z);\n}\n'
)
"""Task 1 divides by zero at 0.001 s (3:5 of its file), then task 0 at 0.010 s (6:5)."""
TASK1 = 'void main() {\n    int z = 0;\n    Print("%d", 2 / z);\n}\n'


def run_cases(root: Path, files: dict[str, str]) -> tuple[int, str]:
    """Write `files` under `root`, run `motionvm test -v` there: (exit code, report)."""
    for name, text in files.items():
        (root / name).write_text(text, encoding="utf-8")
    out = io.StringIO()
    old = os.getcwd()
    os.chdir(root)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            code = main(["test", "-v", "-j", "1"])
    finally:
        os.chdir(old)
    return code, out.getvalue()


def verdicts(report: str) -> dict[str, str]:
    """{case id: PASSED|FAILED|ERROR|XFAIL} from a `-v` report."""
    words = ("PASSED", "FAILED", "ERROR", "XFAIL")
    return {
        line.split()[0]: line.split()[1]
        for line in report.splitlines()
        if len(line.split()) == 2 and line.split()[1] in words
    }


def test_warnings_and_exact_diagnostics(tmp_path: Path) -> None:
    listed = "// expect: hi\n// warning: 2:9: unused variable\n"
    code, report = run_cases(
        tmp_path,
        {
            "listed.hmpl": UNUSED + listed,
            "unlisted_ok.hmpl": UNUSED + "// expect: hi\n",
            "missing.hmpl": UNUSED + "// expect: hi\n// warning: 3:5: unused variable\n",
            "exact.hmpl": UNUSED
            + listed.replace("variable", "variable 'unused'")
            + "// diagnostics: exact\n",
            "exact_partial.hmpl": UNUSED + listed + "// diagnostics: exact\n",
            "exact_unlisted.hmpl": UNUSED + "// expect: hi\n// diagnostics: exact\n",
        },
    )
    assert verdicts(report) == {
        "exact.hmpl": "PASSED",
        "exact_partial.hmpl": "FAILED",  # exact: the whole message
        "exact_unlisted.hmpl": "FAILED",
        "listed.hmpl": "PASSED",
        "missing.hmpl": "FAILED",
        "unlisted_ok.hmpl": "PASSED",  # without `diagnostics: exact`, others may come
    }, report
    assert code == 1
    assert "missing compile warning missing.hmpl:3:5: ...unused variable..." in report
    assert "unexpected compile warning exact_unlisted.hmpl:2:9: unused variable 'unused'" in report


def test_check_cases_compile_only(tmp_path: Path) -> None:
    forever = "void main() {\n    while (1) { Sleep(1); }\n}\n"
    code, report = run_cases(
        tmp_path,
        {
            "forever.hmpl": forever + "// check:\n",  # it would never end if it ran
            "warned.hmpl": UNUSED + "// check:\n",  # a clean compile: no warning either
            "warned_listed.hmpl": UNUSED + "// check:\n// warning: 2:9: unused\n",
            "broken.hmpl": "void main() {\n    x = 1;\n}\n// check:\n// error: 2:5: undeclared\n",
        },
    )
    assert verdicts(report) == {
        "broken.hmpl": "PASSED",
        "forever.hmpl": "PASSED",
        "warned.hmpl": "FAILED",
        "warned_listed.hmpl": "PASSED",
    }, report
    assert code == 1 and "$ motionvm check warned.hmpl" in report
    assert collect([str(tmp_path / "forever.hmpl")])[0].command == "check"


def test_runtime_errors_are_expected_in_order_and_all(tmp_path: Path) -> None:
    both = (
        "// expect: a\n// task 1: two.task1.hmpl\n"
        "// expect runtime error: two.task1.hmpl:3:5: runtime error in task 1\n"
        "// expect runtime error: division by zero\n"
        "// expect runtime error: :6:5: runtime error in task 0 at t=0.010 s:\n"
        "// expect runtime error: division by zero\n"
    )
    swapped = (
        "// expect: a\n// task 1: two.task1.hmpl\n"
        "// expect runtime error: runtime error in task 0\n"
        "// expect runtime error: runtime error in task 1\n"
    )
    code, report = run_cases(
        tmp_path,
        {
            "two.task1.hmpl": TASK1,
            "both.hmpl": TWO_FAULTS + both,
            "swapped.hmpl": TWO_FAULTS + swapped,
            "one.hmpl": TWO_FAULTS
            + "// expect: a\n// task 1: two.task1.hmpl\n// expect runtime error: task 1\n",
        },
    )
    assert verdicts(report) == {
        "both.hmpl": "PASSED",
        "one.hmpl": "FAILED",
        "swapped.hmpl": "FAILED",
    }, report
    assert "unexpected runtime error: one.hmpl:6:5: runtime error in task 0" in report
    assert "missing runtime error containing 'runtime error in task 1' (at or after" in report


def test_restart_runs_the_controller_again_with_one_task(tmp_path: Path) -> None:
    first = 'void main() {\n    Print("first");\n}\n'
    again = 'void main() {\n    Print("after the restart");\n}\n'
    code, report = run_cases(
        tmp_path,
        {
            "power.again.hmpl": again,
            "power.hmpl": first
            + "// restart: power.again.hmpl\n// expect: first\n// expect: after the restart\n",
            "nopower.hmpl": first + "// restart: power.again.hmpl\n// expect: first\n",
        },
    )
    assert verdicts(report) == {"nopower.hmpl": "FAILED", "power.hmpl": "PASSED"}, report
    assert "; motionvm run power.again.hmpl" in report


def test_pending_cases_fail_as_expected_and_may_not_pass(tmp_path: Path) -> None:
    code, report = run_cases(
        tmp_path,
        {
            "later.hmpl": UNUSED + "// pending: prints hello one day\n// expect: hello\n",
            "already.hmpl": UNUSED + "// pending: prints hi one day\n// expect: hi\n",
        },
    )
    assert verdicts(report) == {"already.hmpl": "FAILED", "later.hmpl": "XFAIL"}, report
    assert "passes, but is pending (prints hi one day): remove 'pending:'" in report
    assert "1 passed" not in report and "0 passed, 1 failed, 1 xfailed" in report
    code, report = run_cases(tmp_path, {"already.hmpl": UNUSED + "// expect: hi\n"})
    assert code == 0 and "1 passed, 0 failed, 1 xfailed" in report


def test_a_misspelt_directive_is_an_error(tmp_path: Path) -> None:
    gdl = (
        "MODULE m;\n  INTEGER$VARIABLE v [ ];\nEND$MODULE;\n"
        "| expected: nothing | | error: 9: no column |\n"
    )
    code, report = run_cases(
        tmp_path,
        {
            "typo.hmpl": UNUSED + "// expected: hi\n",
            "typo.gdl": gdl,
            "fine.hmpl": UNUSED + "// expect: hi\n// the expected output is one line\n",
        },
    )
    assert verdicts(report) == {
        "fine.hmpl": "PASSED",
        "typo.gdl": "ERROR",
        "typo.hmpl": "ERROR",
    }, report
    assert "typo.hmpl:5: malformed directive: '// expected: hi'" in report
