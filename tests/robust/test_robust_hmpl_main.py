"""A task's main() takes no parameters: a compile error, not an internal error at run time."""

from __future__ import annotations


def test_main_with_parameters_is_a_compile_error(cli):
    for cmd in ("check", "run"):
        r = cli(cmd, "a.hmpl", a__hmpl='void main(int x) { Print("hi"); }\n')
        assert (r.code, r.stdout) == (2, "")
        assert r.stderr.splitlines()[0] == "a.hmpl:1:15: error: main takes no parameters"


def test_main_void_still_runs(cli):
    r = cli("run", "a.hmpl", a__hmpl='void main(void) { Print("hi"); }\n')
    assert (r.code, r.stdout) == (0, "hi\n")
