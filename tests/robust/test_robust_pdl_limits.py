"""PDL nests if/else, while and loop up to 200 deep (manual 2.2.8): such programs run
(deep loops are flattened, beyond Python's 20 nested blocks); 201 is a located error."""

from __future__ import annotations

import pytest

from motionvm.lang.pdl.parser import MAX_COND_OPERATORS, MAX_PAREN_DEPTH


def _prog(opener: str, depth: int, closer: str = "end;") -> str:
    return (
        "#long s, a;\n#task/0;\ns = 0;\n"
        + (opener + "\n") * depth
        + "s = s + 1;\n"
        + (closer + "\n") * depth
        + 'printl("%d", s);\nhalt;\n'
    )


@pytest.mark.parametrize(
    "opener", ["loop(1) do", "while (s < 1) do", "if (s = 0) do", "loop(2) do\nif (s < 1) do"]
)
@pytest.mark.parametrize("depth", [19, 200])
def test_deep_nests_run(cli, opener, depth):
    if "\n" in opener:
        text = _prog(opener, depth // 2, "end;\nend;")
    else:
        text = _prog(opener, depth)
    r = cli("run", "--until", "0.1s", "a.pdl", a__pdl=text)
    assert (r.code, r.stderr) == (0, ""), r.stderr[:400]
    assert r.stdout.splitlines()[-1].endswith("1"), r.stdout


def test_a_deep_procedure_runs(cli):
    text = (
        "#long s;\nproc f() do\n"
        + "loop(1) do\n" * 30
        + "s = s + 1;\n"
        + "end;\n" * 30
        + 'end;\n#task/0;\ns = 0;\nf();\nprintl("%d", s);\nhalt;\n'
    )
    r = cli("run", "--until", "0.1s", "a.pdl", a__pdl=text)
    assert (r.code, r.stderr) == (0, "")
    assert r.stdout.splitlines()[-1].endswith("1")


def test_past_the_manual_limit_is_a_located_error(cli):
    r = cli("check", "a.pdl", a__pdl=_prog("loop(1) do", 201))
    assert r.code == 2
    assert r.stderr.splitlines()[0] == (
        "a.pdl:204:1: error: blocks nested more than 200 deep (if/else, while and loop count"
        " together)"
    )


def _cond_prog(cond: str) -> str:
    return f'#long s, a;\n#task/0;\na = 1;\ns = 0;\nif ({cond}) s = 7;\nprintl("%d", s);\nhalt;\n'


@pytest.mark.parametrize(
    "cond",
    [
        " & ".join(["a = 1"] * 10_000),
        " & ".join(["~(a > 1)"] * 5_000),
        "(" * MAX_PAREN_DEPTH + "a = 1" + ")" * MAX_PAREN_DEPTH,
    ],
    ids=["10000-terms", "negations", "parentheses"],
)
def test_long_and_deep_conditions_run(cli, cond):
    r = cli("run", "--until", "0.05s", "a.pdl", a__pdl=_cond_prog(cond))
    assert (r.code, r.stderr) == (0, ""), r.stderr[:400]
    assert r.stdout.splitlines()[-1].endswith("7"), r.stdout


@pytest.mark.parametrize(
    ("cond", "message"),
    [
        (
            " & ".join(["a = 1"] * (MAX_COND_OPERATORS + 2)),
            f"more than {MAX_COND_OPERATORS} '&' and '|' in one condition (the limit of PDL)",
        ),
        (
            "(" * (MAX_PAREN_DEPTH + 1) + "a = 1" + ")" * (MAX_PAREN_DEPTH + 1),
            f"parentheses nested more than {MAX_PAREN_DEPTH} deep",
        ),
    ],
    ids=["operators", "parentheses"],
)
def test_past_a_condition_limit_is_a_located_error(cli, cond, message):
    r = cli("check", "a.pdl", a__pdl=_cond_prog(cond))
    assert r.code == 2, r.stderr[:400]
    assert r.stderr.count("error:") == 1
    first = r.stderr.splitlines()[0]
    assert first.startswith("a.pdl:5:") and first.endswith("error: " + message), first[:300]
