"""Loops and switches nested deeper than one generated Python function holds (20 blocks)
keep C's meaning: the inner loops become nested functions, and break, continue, return
with a value, goto, locals, arrays, pointers to locals and task waits work across them."""

from __future__ import annotations

import contextlib
import io
import os

import pytest

from motionvm.cli import main

DEEP = 40  # two splits: the generated function holds 16 loops
KINDS = ("for", "while", "do", "switch")


def _nest(depth: int, inner: str, at: dict[int, tuple[str, str]] | None = None, kinds=KINDS):
    """`depth` nested loops and switches of `kinds` (in turn), each running its body
    once; `at[k]` = (code before, code after) the level-k statement, in its block. A
    counting loop's counter outlives it: `t` sums the counters after their loops."""
    at = at or {}
    opens, closes = "", ""
    for k in range(depth):
        kind = kinds[k % len(kinds)]
        before, after = at.get(k, ("", ""))
        if kind == "for":
            opens += f"{before} int i{k}; for (i{k} = 0; i{k} < 1; i{k}++) {{ "
            closes = f"}} t += i{k}; {after} " + closes
        elif kind == "while":
            opens += f"{before} int w{k} = 0; while (w{k} < 1) {{ w{k}++; "
            closes = f"}} {after} " + closes
        elif kind == "do":
            opens += f"{before} do {{ "
            closes = f"}} while (0); {after} " + closes
        else:
            opens += f"{before} switch ({k}) {{ case {k}: "
            closes = f"}} {after} " + closes
    return opens + inner + " " + closes


def _cli(tmp_path, program: str, *args: str) -> tuple[int, str, str]:
    """`motionvm run ARGS a.hmpl` in-process: (exit code, stdout, stderr)."""
    (tmp_path / "a.hmpl").write_text(program, encoding="utf-8")
    out, err = io.StringIO(), io.StringIO()
    old = os.getcwd()
    os.chdir(tmp_path)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["run", *args, "a.hmpl"])
    finally:
        os.chdir(old)
    return code, out.getvalue(), err.getvalue()


def _run(tmp_path, program: str, *args: str) -> str:
    code, out, err = _cli(tmp_path, program, *args)
    assert (code, err) == (0, ""), err
    return out


def test_return_with_a_value_from_deep_inside(tmp_path):
    prog = f"""
int t;
int f(int x) {{ int v = x; {_nest(DEEP, "v += 1; if (v > 0) return v * 2;")} return -1; }}
void g(int *out) {{ {_nest(DEEP, "*out = 5; return;")} *out = 9; }}
void main() {{ int r = 0; g(&r); Print("%d %d %d", f(3), f(-10), r); }}
"""
    assert _run(tmp_path, prog) == "8 -1 5\n"


def test_return_from_deep_switches_of_a_function_that_never_waits(tmp_path):
    body = _nest(DEEP, "if (x) return 7;", kinds=("switch",))
    prog = f"""int t;
int f(int x) {{ {body} return 2; }}
void main() {{ Print("%d %d", f(1), f(0)); }}
"""
    assert _run(tmp_path, prog) == "7 2\n"


def test_break_and_continue_inside_split_levels(tmp_path):
    inner = """
        for (int a = 0; a < 3; a++) {
            for (int b = 0; b < 3; b++) {
                if (b == 1) continue;
                if (a == 2) break;
                s += 10 * a + b;
            }
        }
        int d = 0;
        do { d++; if (d < 5) continue; s += 100; } while (d < 5);
        int e = 0;
        while (e < 4) { e++; if (e % 2) continue; s += 1000; }
    """
    at = {17: ("", "s += 10000;"), 30: ("", "s += 100000;")}
    prog = f"""int t;
void main() {{ int s = 0; {_nest(DEEP, inner, at)} Print("%d %d", s, t); }}
"""
    assert _run(tmp_path, prog) == f"{24 + 100 + 2000 + 10000 + 100000} {DEEP // 4}\n"


def test_continue_leaves_split_switches(tmp_path):
    switches = _nest(30, "if (k == 2) continue; s += k;", kinds=("switch",))
    prog = f"""int t;
void main() {{
    int s = 0;
    {_nest(10, f"int k = 0; while (k < 3) {{ k++; {switches} }}")}
    Print("%d", s);
}}
"""
    assert _run(tmp_path, prog) == "4\n"


def test_goto_out_of_split_levels(tmp_path):
    prog = f"""int t;
void main() {{
    int n = 0;
again:
    {_nest(DEEP, "n++; if (n < 3) goto again; n += 10;")}
    Print("%d %d", n, t);
}}
"""
    assert _run(tmp_path, prog) == f"13 {DEEP // 4}\n"


def test_locals_arrays_and_pointers_across_splits(tmp_path):
    inner = "v0 += v10 + v25; a[1] = 7; p[2] = 8; *px = 9; v10++; v25 += 2; q[0] = v25;"
    at = {
        10: ("int v10 = 2;", 'Print("v10 %d", v10);'),
        25: ("int v25 = 3; int c[2]; int *q = c;", 'Print("v25 %d %d", v25, c[0]);'),
    }
    prog = f"""int t;
void main() {{
    int v0 = 1; int a[4]; int b[4]; int *p = b; int x = 0; int *px = &x;
    {_nest(DEEP, inner, at)}
    Print("%d %d %d %d %d", v0, a[1], b[2], x, t);
}}
"""
    assert _run(tmp_path, prog) == f"v25 5 5\nv10 3\n6 7 8 9 {DEEP // 4}\n"


def test_sleep_and_till_inside_deep_loops(tmp_path):
    inner = "while (n < 3) { Sleep(10); n++; } Till(n == 3);"
    prog = f"""int t;
void main() {{ int n = 0; {_nest(DEEP, inner)} Print("%d", n); }}
"""
    assert _run(tmp_path, prog, "--stamp") == "[t=0.030000][task 0] 3\n"


def test_recursion_through_split_loops(tmp_path):
    prog = f"""int t;
int r(int d) {{ if (d == 0) return 0; {_nest(20, "return r(d - 1) + 1;")} return -1; }}
void main() {{ Print("%d", r(6)); }}
"""
    assert _run(tmp_path, prog) == "6\n"


@pytest.mark.parametrize("kind", KINDS)
def test_two_hundred_fifty_six_nested_loops_run(tmp_path, kind):
    prog = f"""int t;
void main() {{ int s = 0; {_nest(256, "s += 5;", kinds=(kind,))} Print("%d %d", s, t); }}
"""
    assert _run(tmp_path, prog) == f"5 {0 if kind != 'for' else 256}\n"


def test_a_runtime_error_deep_inside_names_its_place(tmp_path):
    prog = f"""int t;
void main() {{
    int z = 0;
    {_nest(DEEP, "z = 10 / z;")}
}}
"""
    col = prog.splitlines()[3].index("z = 10 / z") + 1  # the statement, as when shallow
    code, out, err = _cli(tmp_path, prog)
    assert code == 1
    assert err.startswith(f"a.hmpl:4:{col}: runtime error in task 0 at t="), err
    assert "division by zero" in err
