"""`motionvm run` and `motionvm test` end a run that can never end at once: exit 124 and
`FILE:LINE:COL: error: task N waits forever: ...` for each wait."""

from __future__ import annotations

WAIT_INPUT = """void main(void)
{
    Print("start");
    Till(GetGPI(5));
}
"""


def test_run_exits_124_naming_each_wait(tmp_path, motionvm):
    (tmp_path / "w.hmpl").write_text(WAIT_INPUT)
    done = motionvm("run", "w.hmpl", cwd=tmp_path)
    assert done.returncode == 124 and done.stdout == "start\n"
    lines = done.stderr.splitlines()
    assert lines[0] == "w.hmpl:4:5: error: task 0 waits forever: in Till"
    assert lines[1].startswith("motionvm: error: the run can never end: at t=")


def test_a_case_that_waits_forever_fails_at_once(tmp_path, motionvm):
    (tmp_path / "w.hmpl").write_text("// expect: start\n" + WAIT_INPUT)
    done = motionvm("test", "-j", "1", "w.hmpl", cwd=tmp_path)
    assert done.returncode == 1
    assert "exit code 124, expected 0" in done.stdout
    assert "w.hmpl:5:5: error: task 0 waits forever: in Till" in done.stdout
    assert "timed out" not in done.stdout
