"""`motionvm test --lf`, `--durations`, `--collect-only` and `--update`."""

from __future__ import annotations

import contextlib
import io
import json
import os
from pathlib import Path

from motionvm.cli import main

OK = 'void main() { Print("ok"); }\n// expect: ok\n'
BAD = 'void main() { Print("bad"); }\n// expect: good\n'
PRINTS = 'void main() {\n    Print("hello");\n    Print("x=%d", 6 * 7);\n}\n'


def write(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return root


def motionvm_test(*argv, cwd: Path) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    old = os.getcwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["test", "-j1", *map(str, argv)])
    finally:
        os.chdir(old)
    return code, out.getvalue(), err.getvalue()


def test_last_failed_reruns_only_the_failures(tmp_path: Path) -> None:
    write(tmp_path, {"a.hmpl": OK, "b.hmpl": BAD, "c.hmpl": OK})
    code, out, _ = motionvm_test(cwd=tmp_path)
    assert code == 1 and "2 passed, 1 failed" in out
    cache = tmp_path / ".motionvm_cache"
    assert json.loads((cache / "lastfailed.json").read_text()) == ["b.hmpl"]
    assert (cache / ".gitignore").read_text().endswith("*\n")
    assert not list(cache.glob("*.tmp"))  # written atomically: no leftover
    code, out, _ = motionvm_test("--lf", cwd=tmp_path)
    assert code == 1
    assert "run-last-failure: rerun previous 1 failure" in out
    assert "collected 1 case (2 deselected)" in out and "0 passed, 1 failed" in out
    # fixed: it passes, is forgotten, and --lf runs everything again
    (tmp_path / "b.hmpl").write_text(OK)
    code, out, _ = motionvm_test("--lf", cwd=tmp_path)
    assert code == 0 and "1 passed, 0 failed" in out
    assert json.loads((cache / "lastfailed.json").read_text()) == []
    code, out, _ = motionvm_test("--lf", cwd=tmp_path)
    assert "no previously failed cases, running all" in out and "3 passed" in out


def test_last_failed_keeps_the_failures_of_cases_not_run(tmp_path: Path) -> None:
    write(tmp_path, {"a.hmpl": BAD, "b.hmpl": BAD})
    motionvm_test(cwd=tmp_path)
    (tmp_path / "a.hmpl").write_text(OK)
    motionvm_test("-k", "a", cwd=tmp_path)
    cache = tmp_path / ".motionvm_cache" / "lastfailed.json"
    assert json.loads(cache.read_text()) == ["b.hmpl"]
    cache.write_text("{not json")  # a damaged cache is an empty one
    code, out, _ = motionvm_test("--lf", cwd=tmp_path)
    assert "running all" in out and code == 1


def test_durations_lists_the_slowest_cases(tmp_path: Path) -> None:
    write(tmp_path, {"a.hmpl": OK, "b.hmpl": OK, "c.hmpl": OK})
    code, out, _ = motionvm_test("--durations", "2", cwd=tmp_path)
    assert code == 0
    section = out.split("slowest 2 durations", 1)[1].splitlines()[1:3]
    assert all(line.split("s ", 1)[1] in ("a.hmpl", "b.hmpl", "c.hmpl") for line in section)
    times = [float(line.split("s ", 1)[0]) for line in section]
    assert times == sorted(times, reverse=True)
    assert out.index("slowest") < out.index("3 passed")
    code, out, _ = motionvm_test("--durations", "0", cwd=tmp_path)
    assert "slowest durations" in out and out.count(".hmpl\n") == 3
    code, _, err = motionvm_test("--durations", "-1", cwd=tmp_path)
    assert code == 3 and "--durations" in err


def test_collect_only_lists_without_running(tmp_path: Path) -> None:
    write(tmp_path, {"a.hmpl": OK, "sub/b.hmpl": BAD, "notes.hmpl": PRINTS})
    code, out, _ = motionvm_test("--collect-only", cwd=tmp_path)
    assert code == 0
    assert out == "a.hmpl\nsub/b.hmpl\n\n2 cases collected\n"
    assert not (tmp_path / ".motionvm_cache").exists()  # nothing ran
    code, out, _ = motionvm_test("--collect-only", "-k", "sub", cwd=tmp_path)
    assert out == "sub/b.hmpl\n\n1 case collected (1 deselected)\n"
    code, out, _ = motionvm_test("--collect-only", "-k", "zzz", cwd=tmp_path)
    assert code == 5


def test_update_rewrites_out_files_from_the_actual_output(tmp_path: Path) -> None:
    write(
        tmp_path,
        {
            "stale.hmpl": PRINTS,
            "stale.out": "hello\nx=41\n",
            "fine.hmpl": PRINTS,
            "fine.out": "hello\nx=42\n",
            "inline.hmpl": BAD,  # inline expectations are not rewritten
            "crash.hmpl": 'void main() { int z = 0; Print("%d", 1 / z); }\n',
            "crash.out": "",  # exit 1: the run does not meet its expectations otherwise
        },
    )
    code, out, _ = motionvm_test("--update", cwd=tmp_path)
    assert code == 1
    assert "updated 1 .out file: stale.out" in out
    assert (tmp_path / "stale.out").read_text() == "hello\nx=42\n"
    assert (tmp_path / "crash.out").read_text() == ""
    assert "FAILED crash.hmpl" in out and "FAILED inline.hmpl" in out
    assert "2 passed, 2 failed" in out
    code, out, _ = motionvm_test("-k", "stale", cwd=tmp_path)
    assert code == 0


def test_unchanged_cases_come_from_the_results_cache(tmp_path: Path) -> None:
    write(tmp_path, {"a.hmpl": OK, "b.hmpl": BAD, "c.out": "hello\nx=42\n", "c.hmpl": PRINTS})
    first = motionvm_test(cwd=tmp_path)
    assert "from cache" not in first[1]
    code, out, _ = motionvm_test(cwd=tmp_path)
    assert code == 1 and "1 failed in" in out and out.rstrip().endswith("(3 from cache)")
    assert "+bad" in out  # judged again from the stored output: the same report
    # an edited file runs again (every case of its folder: their keys hold its bytes)
    (tmp_path / "b.hmpl").write_text(OK)
    code, out, _ = motionvm_test(cwd=tmp_path)
    assert code == 0 and "3 passed" in out and "from cache" not in out
    # a changed expectation is judged against the stored output, not run again
    (tmp_path / "sub").mkdir()
    write(tmp_path, {"sub/d.hmpl": OK})
    motionvm_test(cwd=tmp_path)
    (tmp_path / "sub" / "d.hmpl").write_text(OK + "// expect: more\n")
    code, out, _ = motionvm_test("-k", "d.hmpl", cwd=tmp_path)
    assert code == 1 and "from cache" not in out
    code, out, _ = motionvm_test("--cache-clear", cwd=tmp_path)
    assert "from cache" not in out


def test_timed_out_cases_are_never_cached(tmp_path: Path) -> None:
    from motionvm.cli import resultcache
    from motionvm.cli.workers import Outcome

    assert not resultcache.cacheable(Outcome(None, "", "", 1.0, timed_out=True))
    assert not resultcache.cacheable(Outcome(None, "", "", 1.0, crashed="killed by SIGKILL"))
    assert not resultcache.cacheable(Outcome(None, "x", "", 1.0, flooded=True))
    assert not resultcache.cacheable(Outcome(130, "", "motionvm: interrupted", 1.0))
    assert resultcache.cacheable(Outcome(1, "", "", 1.0))
    write(tmp_path, {"hang.hmpl": "void main() {\n    while (1) { Sleep(1); }\n}\n// expect: x\n"})
    for _ in range(2):
        code, out, _ = motionvm_test("--case-timeout", "1", cwd=tmp_path)
        assert code == 1 and "timed out" in out and "from cache" not in out


def test_repeat_runs_each_case_n_times_and_fails_differing_runs(
    tmp_path: Path, monkeypatch
) -> None:
    import dataclasses

    from motionvm.cli import workers

    write(tmp_path, {"a.hmpl": OK, "b.hmpl": OK})
    real = workers.local_outcomes
    seen: list[int] = []

    def flaky(cases, jobs, timeout, coverage=False):
        """The real runs; the second run of b.hmpl prints something else."""
        for k, outcome in real(cases, jobs, timeout, coverage):
            seen.append(k)
            if cases[k].id == "b.hmpl" and sum(cases[j].id == "b.hmpl" for j in seen) == 2:
                outcome = dataclasses.replace(outcome, stdout="ok\nstray\n")
            yield k, outcome

    monkeypatch.setattr(workers, "local_outcomes", flaky)
    code, out, _ = motionvm_test("--repeat", "3", cwd=tmp_path)
    assert len(seen) == 6 and "from cache" not in out
    assert code == 1 and "1 passed, 1 failed" in out
    assert "run 2 of 3 differs from run 1 (--repeat: the program is not deterministic)" in out
    assert "+stray" in out
    monkeypatch.setattr(workers, "local_outcomes", real)
    code, out, _ = motionvm_test("--repeat", "2", cwd=tmp_path)
    assert code == 0 and "2 passed" in out
    code, _, err = motionvm_test("--repeat", "0", cwd=tmp_path)
    assert code == 3 and "--repeat" in err
