"""The HMPL compiler's limits: legal programs well inside them compile and run; past a
limit the error names it at the place (exit 2), never an internal error (exit 4)."""

from __future__ import annotations

import pytest

from motionvm.lang.hmpl.lower_util import MAX_LOOP_NESTING
from motionvm.lang.hmpl.parser import MAX_OPERATORS


def _main(body: str, pre: str = "") -> str:
    return pre + "void main() {\n    int s = 0;\n" + body + "\n}\n"


def _loops(kinds: list[str], inner: str, count: int = 2) -> str:
    opens = closes = ""
    for k, kind in enumerate(kinds):
        if kind == "for":
            opens += f"for (int i{k} = 0; i{k} < {count}; i{k}++) {{ "
            closes = "} " + closes
        elif kind == "while":
            opens += f"while (s < {k + 1}) {{ "
            closes = "} " + closes
        elif kind == "do":
            opens += "do { "
            closes = "} while (0); " + closes
        else:
            opens += "switch (s & 1) { default: "
            closes = "} " + closes
    return opens + inner + " " + closes


@pytest.mark.parametrize("kind", ["for", "while", "do", "switch", "mixed"])
def test_loops_and_switches_nested_to_the_limit_run(cli, kind):
    kinds = (
        ["for", "while", "do", "switch"] * MAX_LOOP_NESTING
        if kind == "mixed"
        else [kind] * MAX_LOOP_NESTING
    )[:MAX_LOOP_NESTING]
    # a frame (an address-taken array), a goto dispatcher and a Till innermost: the
    # Python blocks the function needs besides the loops
    body = (
        "int a[2]; int *p = a; a[0] = 1;\nagain:\n"
        + _loops(kinds, "s += p[0]; Till(s > 0);", count=1)
        + '\nif (s < 0) goto again;\nPrint("%d", s > 0);'
    )
    r = cli("run", "--until", "1s", "a.hmpl", a__hmpl=_main(body))
    assert (r.code, r.stdout, r.stderr) == (0, "1\n", "")


def test_eleven_nested_for_loops_run(cli):
    body = _loops(["for"] * 11, "s++;") + '\nPrint("%d", s);'
    r = cli("run", "a.hmpl", a__hmpl=_main(body))
    assert (r.code, r.stdout) == (0, f"{2**11}\n")


@pytest.mark.parametrize("kind", ["for", "while", "do", "switch"])
def test_one_loop_past_the_limit_is_a_located_error(cli, kind):
    body = _loops([kind] * (MAX_LOOP_NESTING + 1), "s++;")
    for cmd in ("check", "run"):
        r = cli(cmd, "a.hmpl", a__hmpl=_main(body))
        assert r.code == 2, r.stderr
        first = r.stderr.splitlines()[0]
        assert first.startswith("a.hmpl:3:") and first.endswith(
            f"error: loops and switches nested more than {MAX_LOOP_NESTING} deep in one"
            " function (the limit of HMPL); move the inner ones into a function"
        ), first
        assert r.stderr.count("error:") == 1


def test_ten_thousand_terms(cli):
    body = "int a = 1;\n    s = " + " + ".join(["a"] * 10_000) + ';\n    Print("%d", s);'
    r = cli("run", "a.hmpl", a__hmpl=_main(body))
    assert (r.code, r.stdout, r.stderr) == (0, "10000\n", "")
    body = "double d = 0.5;\n    double e = " + " * ".join(["d"] * 2_000) + ";\n"
    body += "    s = " + " - ".join(["1"] * 10_000) + ';\n    Print("%d %g", s, e);'
    r = cli("run", "a.hmpl", a__hmpl=_main(body))
    assert (r.code, r.stdout, r.stderr) == (0, "-9998 0\n", "")
    body = "int a = 3, b = 2, c = 1;\n    s = " + " - ".join(["a * b - c"] * 3_334) + ";\n"
    body += "    s = s + " + " + ".join(["-a"] * 10_000) + ';\n    Print("%d", s);'
    r = cli("run", "a.hmpl", a__hmpl=_main(body))
    assert (r.code, r.stdout, r.stderr) == (0, f"{6 - 3333 * 7 - 1 - 30_000}\n", "")


def test_too_many_operators_is_a_located_error(cli):
    body = "s = " + "+".join(["1"] * (MAX_OPERATORS + 2)) + ";"
    r = cli("check", "a.hmpl", a__hmpl=_main(body))
    assert r.code == 2
    assert f"error: more than {MAX_OPERATORS} operators in a row" in r.stderr


@pytest.mark.parametrize(
    ("body", "out"),
    [
        ("if (s == 0) " * 256 + "s = 7;", "7"),
        ("if (s == 0) {" * 256 + "s = 7;" + "}" * 256, "7"),
        ("if (s == 1) s = 2; else " * 256 + "s = 7;", "7"),
        ("{" * 1000 + "s = 7;" + "}" * 1000, "7"),
        ("s = 7; s = " + "- " * 256 + "s;", "7"),
        ("s = 7; s = " + "-(" * 256 + "s" + ")" * 256 + ";", "7"),
        ("s = 7; s = " + "!" * 255 + "s;", "0"),
        ("s = " + "(" * 1000 + "7" + ")" * 1000 + ";", "7"),
        ("s = " + "f(" * 256 + "0" + ")" * 256 + ";", "256"),
        ("struct N n; n.next = &n; n.v = 7; s = n.next" + "->next" * 325 + "->v;", "7"),
    ],
    ids=[
        "if",
        "if-block",
        "else-if",
        "blocks",
        "minus",
        "minus-paren",
        "not",
        "parens",
        "calls",
        "members",
    ],
)
def test_deep_legal_programs_run(cli, body, out):
    pre = "int f(int x) { return x + 1; }\nstruct N { struct N *next; int v; };\n"
    r = cli("run", "a.hmpl", a__hmpl=_main(body + '\nPrint("%d", s);', pre))
    assert (r.code, r.stderr, r.stdout) == (0, "", out + "\n")


def test_nesting_past_the_parser_limit_is_one_error(cli):
    body = "{" * 3000 + "s = 7;" + "}" * 3000
    r = cli("check", "a.hmpl", a__hmpl=_main(body))
    assert r.code == 2
    assert r.stderr.count("error:") == 1, r.stderr[:500]
    assert "nesting deeper than" in r.stderr
