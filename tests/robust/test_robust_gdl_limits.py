"""Deep GDL programs compile and run: nested parentheses, long expressions, WHILE loops
nested past Python's 20 blocks (a RETURN deep inside still leaves the procedure)."""

from __future__ import annotations

import pytest

from motionvm.lang.gdl.parser import MAX_NESTING, MAX_OPERATORS

SCENARIO = '[[event]]\nat = 0.010\nset = "STATUS OF go"\nvalue = "ON"\n'


def _app(body: str) -> str:
    return (
        "MODULE m;\n  INTEGER$VARIABLE s [ ];\n  INTEGER$VARIABLE a [ INITIAL$VALUE = 1 ];\n"
        "  DIGITAL$FLAG go [ ];\n  PROCEDURE p;\n  DECLARE { STATUS OF go };\n  BEGIN\n"
        + body
        + "\n  END$PROCEDURE;\nEND$MODULE;\n"
    )


def _run(cli, body: str):
    r = cli(
        "run",
        "--scenario",
        "s.toml",
        "--until",
        "0.1s",
        "a.gdl",
        a__gdl=_app(body),
        s__toml=SCENARIO,
    )
    assert (r.code, r.stderr) == (0, ""), r.stderr[:500]
    return [line for line in r.stdout.splitlines() if "set VALUE OF s" in line]


@pytest.mark.parametrize(
    ("body", "last"),
    [
        ("VALUE OF s = " + "(" * 300 + "VALUE OF a" + ")" * 300 + ";", 1),
        ("VALUE OF s = " + " + ".join(["VALUE OF a"] * 10_000) + ";", 10_000),
        ("VALUE OF s = " + " - ".join(["VALUE OF a * 2"] * 5_000) + ";", -9_996),
        ("VALUE OF s = " + " - ".join(["VALUE OF a"] * 1000) + ";", -998),
        (
            "VALUE OF s = 0;\n"
            + "IF VALUE OF s = 0 THEN\n" * 256
            + "VALUE OF s = 7;\n"
            + "END$IF;\n" * 256,
            7,
        ),
        (
            "VALUE OF s = 0;\n"
            + "WHILE VALUE OF s < 1 DO\n" * 256
            + "VALUE OF s = VALUE OF s + 1;\n"
            + "END$WHILE;\n" * 256,
            1,
        ),
        (
            "VALUE OF s = 0;\nIF "
            + "NOT " * 256
            + "(VALUE OF s = 0) THEN\nVALUE OF s = 7;\nEND$IF;",
            7,
        ),
    ],
    ids=["parens", "plus", "mixed", "minus", "if", "while", "not"],
)
def test_deep_programs_run(cli, body, last):
    lines = _run(cli, body)
    assert lines[-1].endswith(f"set VALUE OF s = {last}"), lines[-3:]


def test_return_deep_in_nested_whiles_leaves_the_procedure(cli):
    body = (
        "VALUE OF s = 0;\n"
        + "WHILE VALUE OF s < 5 DO\n" * 40
        + "VALUE OF s = VALUE OF s + 1;\nIF VALUE OF s = 3 THEN\nRETURN;\nEND$IF;\n"
        + "END$WHILE;\n" * 40
        + "VALUE OF s = 99;\n"
    )
    lines = _run(cli, body)
    assert [x.rsplit("= ", 1)[1] for x in lines] == ["1", "2", "3"]  # and never 99


@pytest.mark.parametrize(
    ("body", "where", "message"),
    [
        (
            "VALUE OF s = 0;\n"
            + "IF VALUE OF s = 0 THEN\n" * (MAX_NESTING + 1)
            + "VALUE OF s = 7;\n"
            + "END$IF;\n" * (MAX_NESTING + 1),
            f":{9 + MAX_NESTING}:1:",
            f"nesting deeper than {MAX_NESTING} levels (the limit of GDL); the rest of the file"
            " is not parsed",
        ),
        (
            "VALUE OF s = " + "(" * (MAX_NESTING + 1) + "1" + ")" * (MAX_NESTING + 1) + ";",
            f":8:{14 + MAX_NESTING}:",
            f"nesting deeper than {MAX_NESTING} levels (the limit of GDL); the rest of the file"
            " is not parsed",
        ),
        (
            "VALUE OF s = " + " + ".join(["1"] * (MAX_OPERATORS + 2)) + ";",
            f":8:{16 + 4 * MAX_OPERATORS}:",
            f"more than {MAX_OPERATORS} operators in a row (the limit of GDL)",
        ),
    ],
    ids=["if", "parens", "operators"],
)
def test_past_a_limit_is_one_located_error(cli, body, where, message):
    r = cli("check", "a.gdl", a__gdl=_app(body))
    assert r.code == 2, r.stderr[:400]
    assert r.stderr.count("error:") == 1, r.stderr[:400]
    first = r.stderr.splitlines()[0]
    assert first.startswith("a.gdl" + where) and first.endswith("error: " + message), first[:300]
