"""Shift counts: a negative one is a run-time fault, folded or not; one of the width or
more is taken modulo the width, folded or not."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize(
    "expr",
    ["one >> s", "one << s", "i >> s", "1LL >> -1", "1 << -1", "i >>= s"],
)
def test_a_negative_shift_count_is_a_runtime_fault(cli, expr):
    text = (
        "void main() {\n    long long one = 1;\n    long long s = -1;\n    int i = 4;\n"
        f'    Print("before");\n    i = ({expr});\n    Print("not reached %lld %lld", one, s);\n}}\n'
    )
    r = cli("run", "a.hmpl", a__hmpl=text)
    assert (r.code, r.stdout) == (1, "before\n")
    assert r.stderr.splitlines()[-1] == (
        "a.hmpl:6:5: runtime error in task 0 at t=0.000 s: negative shift count -1"
    )


def test_shift_counts_past_the_width_fold_as_they_run(cli):
    text = """void main() {
    long long one = 1;
    long long s = 65;
    unsigned int u = 33;
    int i = -5;
    Print("%lld %lld %lld %lld", one << s, one >> s, 1LL << 65, 1LL >> 65);
    Print("%d %d %d %d", i >> u, i << u, -5 >> 33, -5 << 33);
    Print("%lld %lld", one << 100, 1LL << 100);
}
"""
    r = cli("run", "a.hmpl", a__hmpl=text)
    assert (r.code, r.stdout) == (0, "2 0 2 0\n-3 -10 -3 -10\n68719476736 68719476736\n")
