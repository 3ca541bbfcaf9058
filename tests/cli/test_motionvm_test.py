"""`motionvm test`: cases of every language, both kinds of expectations, the report,
selection, -x, JUnit XML, exit codes, the worker pool's timeout and a Dask cluster."""

from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from motionvm.cli import main
from motionvm.cli.cases import Case, collect
from motionvm.cli.exits import UsageError
from motionvm.cli.test import select

REPO = Path(__file__).resolve().parents[2]

PRINTS = 'void main() {\n    Print("hello");\n    Print("x=%d", 6 * 7);\n}\n'
GDL = """| a counter of button presses |
MODULE cell;
  IO$BOARD io [ SLOT = 1 ];
  DIGITAL$INPUT button [ BOARD$NAME = io, CHANNEL = 1 ];
  INTEGER$VARIABLE presses [ ];

  PROCEDURE count;
  DECLARE { STATUS OF button };
  BEGIN
    VALUE OF presses = VALUE OF presses + 1;
  END$PROCEDURE;
END$MODULE;
"""
GDL_TRACE = (
    "t=0.100 input STATUS OF button = ON\nt=0.100 run count\nt=0.100 set VALUE OF presses = 1\n"
)
SCENARIO = '[[event]]\nat = 0.100\nset = "STATUS OF button"\nvalue = "ON"\n'

SUITE = {
    # HMPL: a .out file, inline lines, a runtime error, a compile error, task files
    "hmpl/hello.hmpl": PRINTS,
    "hmpl/hello.out": "hello\nx=42\n",
    "hmpl/inline.hmpl": PRINTS.replace('("hello");', '("hello"); // expect: hello')
    + "// expect: x=42\n",
    "hmpl/wrong.hmpl": PRINTS + "// expect: hello\n// expect: x=41\n",
    "hmpl/divide.hmpl": 'void main() {\n    int z = 0;\n    Print("%d", 1 / z);\n}\n'
    "// expect runtime error: division by zero\n",
    "hmpl/syntax.hmpl": 'void main() {\n    int x = 1\n    Print("%d", x);\n}\n'
    "// error: 2:14: expected ';'\n",
    "hmpl/two.hmpl": 'void main() { StartTask(1); Print("task 0"); }\n',
    "hmpl/two.task1.hmpl": 'void main() { Sleep(5); Print("task 1"); }\n',
    "hmpl/two.out": "task 0\ntask 1\n",
    "hmpl/until.hmpl": 'void main() {\n    while (1) { Sleep(1000); Print("tick"); }\n}\n'
    "// args: --until 2.5\n// expect: tick\n// expect: tick\n",
    "hmpl/notes.hmpl": 'void main() { Print("no expectation: not a case"); }\n',
    # PDL: inline lines, a .out file that differs, a compile error
    "pdl/answer.pdl": '#long n;\n#task/0;\nn = 6 * 7;\nprintl("n=%ld", n); // expect: n=42\nhalt;\n',
    "pdl/stale.pdl": '#long n;\n#task/0;\nn = 6 * 7;\nprintl("n=%ld", n);\nhalt;\n',
    "pdl/stale.out": "n=41\n",
    "pdl/broken.pdl": "#long n;\n#task/0;\nn = 1\nhalt;\n// error: 3:6: expected ';'\n",
    # GDL: a scenario with a .out file, inline `| expect: |` lines, a compile error
    "gdl/count.gdl": GDL,
    "gdl/count.toml": SCENARIO,
    "gdl/count.out": GDL_TRACE,
    "gdl/inline.gdl": GDL + "".join(f"| expect: {line} |\n" for line in GDL_TRACE.splitlines()),
    "gdl/inline.toml": SCENARIO,
    "gdl/unknown.gdl": GDL.replace("STATUS OF button }", "STATUS OF buton }")
    + "| error: 8:23: unknown object 'buton' |\n",
}
PASSING = 11
FAILING = ["hmpl/wrong.hmpl", "pdl/stale.pdl"]


def write(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return root


def motionvm_test(*argv, cwd: Path) -> tuple[int, str, str]:
    """`motionvm test ARGV` in this process (the cases run in worker processes)."""
    out, err = io.StringIO(), io.StringIO()
    old = os.getcwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["test", *map(str, argv)])
    finally:
        os.chdir(old)
    return code, out.getvalue(), err.getvalue()


def untimed(report: str) -> str:
    return re.sub(r" in \d+\.\d+ s$", " in S s", report.rstrip("\n"), flags=re.M)


@pytest.fixture(scope="module")
def suite(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write(tmp_path_factory.mktemp("suite"), SUITE)


@pytest.fixture(scope="module")
def suite_report(suite: Path) -> tuple[int, str, str]:
    return motionvm_test("-j", "2", cwd=suite)


def test_collects_programs_with_expectations_only(suite: Path, monkeypatch) -> None:
    monkeypatch.chdir(suite)
    ids = [c.id for c in collect(["."])]
    assert ids == sorted(ids)
    assert "hmpl/notes.hmpl" not in ids  # no expectation
    assert "hmpl/two.task1.hmpl" not in ids  # a companion
    assert len(ids) == PASSING + len(FAILING)
    two = next(c for c in collect(["hmpl/two.hmpl"]))
    assert two.argv == ("two.hmpl", "two.task1.hmpl")
    count = collect(["gdl/count.gdl"])[0]
    assert count.argv == ("count.gdl", "--scenario", "count.toml")


def test_report_of_passing_and_failing_cases(suite_report) -> None:
    code, out, err = suite_report
    assert code == 1, out + err
    assert err == ""
    lines = out.splitlines()
    assert lines[0] == f"collected {PASSING + len(FAILING)} cases"
    progress = lines[2]
    assert sorted(progress) == sorted("." * PASSING + "F" * len(FAILING))
    assert lines[-1].startswith(f"{PASSING} passed, 2 failed in ")
    for case in FAILING:
        assert f"FAILED {case}" in lines
    # a unified diff of the expected and the actual stdout
    assert "--- pdl/stale.out\n" not in out
    assert "--- stale.out\n+++ actual stdout\n" in out
    assert "-n=41\n+n=42\n" in out
    assert "-x=41\n+x=42\n" in out


def test_same_report_whatever_the_number_of_workers(suite: Path, suite_report) -> None:
    code, out, _ = motionvm_test("-j", "1", "--cache-clear", cwd=suite)
    assert code == suite_report[0]
    assert untimed(out) == untimed(suite_report[1])


def test_select_with_k_and_stop_with_x(suite: Path) -> None:
    code, out, _ = motionvm_test("-j1", "-k", "gdl", cwd=suite)
    assert code == 0
    assert out.startswith(f"collected 3 cases ({PASSING + len(FAILING) - 3} deselected)")
    assert "3 passed, 0 failed" in out
    code, out, _ = motionvm_test("-j1", "-k", "not hmpl", "-v", cwd=suite)
    assert code == 1
    assert "pdl/stale.pdl FAILED" in out and "hmpl/" not in out
    code, out, _ = motionvm_test("-j2", "-x", "-q", cwd=suite)
    assert code == 1
    assert "stopping after the first failure" in out
    # cases in path order: gdl/* (3), hmpl/divide, hello, inline, syntax, two, until, wrong
    assert re.search(r"^\.{9}F$", out, re.M), out
    assert "9 passed, 1 failed" in out
    assert "pdl/stale" not in out


def test_junit_xml(suite: Path, tmp_path: Path) -> None:
    report = tmp_path / "report.xml"
    code, _, _ = motionvm_test("-q", "--junitxml", report, cwd=suite)
    assert code == 1
    assert [p.name for p in tmp_path.iterdir()] == ["report.xml"]  # no temporary file left
    root = ET.parse(report).getroot()
    suite_node = root.find("testsuite")
    assert suite_node is not None
    assert suite_node.get("tests") == str(PASSING + len(FAILING))
    assert suite_node.get("failures") == "2" and suite_node.get("errors") == "0"
    cases = {c.get("file"): c for c in suite_node.iter("testcase")}
    assert cases["hmpl/hello.hmpl"].get("classname") == "hmpl"
    assert cases["hmpl/hello.hmpl"].get("name") == "hello.hmpl"
    assert cases["hmpl/hello.hmpl"].find("failure") is None
    failure = cases["hmpl/wrong.hmpl"].find("failure")
    assert failure is not None and "+x=42" in (failure.text or "")
    assert cases["hmpl/wrong.hmpl"].find("system-out").text == "hello\nx=42\n"


def test_exit_codes_of_bad_usage_and_empty_runs(tmp_path: Path) -> None:
    write(tmp_path, {"a.hmpl": PRINTS, "a.out": "hello\nx=42\n", "empty/notes.txt": ""})
    assert motionvm_test("missing", cwd=tmp_path)[0] == 3
    code, _, err = motionvm_test("a.out", cwd=tmp_path)
    assert code == 3 and "not a program" in err
    assert motionvm_test("-j", "0", cwd=tmp_path)[0] == 3
    assert motionvm_test("--case-timeout", "0", cwd=tmp_path)[0] == 3
    code, out, _ = motionvm_test("empty", cwd=tmp_path)
    assert code == 5 and "no cases found" in out
    code, out, _ = motionvm_test("-k", "nothing", cwd=tmp_path)
    assert code == 5 and "(1 deselected)" in out
    assert motionvm_test("a.hmpl", cwd=tmp_path)[0] == 0


def test_a_malformed_case_is_an_error_not_a_crash(tmp_path: Path) -> None:
    write(
        tmp_path,
        {
            "bad.hmpl": PRINTS + "// error: two:14: expected\n",
            "both.hmpl": PRINTS + "// expect: hello\n",
            "both.out": "hello\nx=42\n",
        },
    )
    code, out, err = motionvm_test("-j1", cwd=tmp_path)
    assert code == 1 and err == ""
    assert "EE" in out and "0 passed, 0 failed, 2 errors in" in out
    assert "want 'error: [FILE:]LINE:COL: TEXT'" in out
    assert "both both.out and inline" in out


def test_a_hanging_program_hits_the_case_timeout(tmp_path: Path) -> None:
    """The limit is generous for the quick case (a tenth of a second of its own run: the
    clock starts after its worker imported the compiler) and the hanging program never
    ends (no simulated time limit, a loop without exit). Two workers run both at once, so
    the test lasts about the limit."""
    write(
        tmp_path,
        {
            "hang.hmpl": "void main() {\n    while (1) { Sleep(1); }\n}\n// expect: never\n",
            "quick.hmpl": PRINTS,
            "quick.out": "hello\nx=42\n",
        },
    )
    code, out, _ = motionvm_test("-j2", "--case-timeout", "2", cwd=tmp_path)
    assert code == 1
    assert "F." in out
    assert "hang.hmpl" in out and "timed out after 2 s of wall-clock time" in out
    assert "1 passed, 1 failed" in out


def test_a_case_clock_starts_after_the_imports_of_its_languages() -> None:
    from motionvm.cli.workers import preload_modules

    hmpl = Case("a.hmpl", "/", ("a.hmpl",))
    gdl = Case("b.gdl", "/", ("b.gdl", "--scenario", "s.toml"))
    assert preload_modules([hmpl]) == (
        "motionvm.cli.run",
        "motionvm.session",
        "motionvm.lang.hmpl.compiler",
        "motionvm.lang.hmpl.rtapi",
    )
    assert "motionvm.lang.gdl.compiler" in preload_modules([hmpl, gdl])
    assert not any("pdl" in m for m in preload_modules([hmpl, gdl]))


def test_the_examples_pass() -> None:
    code, out, err = motionvm_test("examples", cwd=REPO)
    assert code == 0, out + err
    n = len(collect([str(REPO / "examples")]))
    assert n >= 4 and f"{n} passed, 0 failed" in out


def test_through_a_subprocess(suite: Path) -> None:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO / "src") + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run(
        [sys.executable, "-m", "motionvm", "test", "-q", "-j", "2", "gdl", "pdl/answer.pdl"],
        cwd=suite,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.splitlines()[-1].startswith("4 passed, 0 failed in ")
    assert proc.stderr == ""


def test_dask_cluster(suite: Path) -> None:
    distributed = pytest.importorskip("dask.distributed", reason="dask is not installed")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        code, out, err = motionvm_test(
            "--dask", cluster.scheduler_address, "pdl", "--cache-clear", cwd=suite
        )
    assert code == 1, out + err
    assert "FAILED pdl/stale.pdl" in out
    local = motionvm_test("-j", "2", "pdl", "--cache-clear", cwd=suite)[1]
    assert untimed(out).replace(f" on the Dask cluster at {cluster.scheduler_address}", "") == (
        untimed(local)
    )


def test_dask_missing_names_the_extra(suite: Path, monkeypatch) -> None:
    monkeypatch.setitem(sys.modules, "dask", None)
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    code, _, err = motionvm_test("--dask", "tcp://127.0.0.1:1", cwd=suite)
    assert code == 3
    assert "pip install 'motionvm[cluster]'" in err


def test_run_arguments_of_directives_and_companions(tmp_path: Path) -> None:
    write(
        tmp_path,
        {
            "cell.hmpl": PRINTS
            + "// task 3: cell.task1.hmpl\n// expect: hello\n// args: --until 1\n",
            "cell.task1.hmpl": PRINTS,
            "cell.toml": "",
            "cell.b10.gdl": GDL,
            "cell.b9.gdl": GDL,
            "cell.scenario.toml": SCENARIO,
        },
    )
    (case,) = collect([str(tmp_path)])
    assert case.argv == (
        "--until",
        "1",
        "cell.hmpl",
        "--task",
        "3=cell.task1.hmpl",
        "--machine",
        "cell.toml",
        "cell.b9.gdl",
        "cell.b10.gdl",
        "--scenario",
        "cell.scenario.toml",
    )
    assert case.expect.stdout == (("text", "hello"),) and case.expect.exit_code == 0


@pytest.mark.parametrize(
    "expr, chosen",
    [
        ("hello", ["hmpl/hello.hmpl"]),
        ("HELLO", ["hmpl/hello.hmpl"]),
        ("not hmpl", ["pdl/stale.pdl"]),
        ("hmpl and not hello", ["hmpl/wrong.hmpl"]),
        ("stale or hello", ["hmpl/hello.hmpl", "pdl/stale.pdl"]),
        ("(stale or hello) and not pdl", ["hmpl/hello.hmpl"]),
        ("not (hello or wrong)", ["pdl/stale.pdl"]),
        ("hmpl and (not hello)", ["hmpl/wrong.hmpl"]),
    ],
)
def test_k_expressions(expr: str, chosen: list[str]) -> None:
    cases = [Case(i, "/", ()) for i in ("hmpl/hello.hmpl", "hmpl/wrong.hmpl", "pdl/stale.pdl")]
    assert [c.id for c in select(cases, expr)] == chosen


@pytest.mark.parametrize(
    "expr, message",
    [
        ("(hello or", "expected a word, 'not' or '(' at the end"),
        ("hello)", "unexpected ')' at column 6"),
        ("hello and or x", "expected a word, 'not' or '(' at column 11, got 'or'"),
        ("(a or b", "expected ')' at the end"),
        ("   ", "empty expression"),
    ],
)
def test_a_k_expression_that_does_not_parse_is_a_usage_error(expr: str, message: str) -> None:
    cases = [Case("hmpl/hello.hmpl", "/", ())]
    with pytest.raises(UsageError, match=re.escape(message)):
        select(cases, expr)


@pytest.mark.parametrize(("count", "slots"), [(0, 2), (1, 2), (7, 1), (100, 2), (1000, 3), (5, 64)])
def test_dask_cases_go_in_batches_of_consecutive_cases(count: int, slots: int) -> None:
    from motionvm.cli.workers import batches

    parts = batches(count, slots)
    assert [i for part in parts for i in part] == list(range(count))
    assert len(parts) <= 4 * slots
    if count >= 4 * slots:
        assert len(parts) >= 2 * slots  # every slot keeps busy to the end
