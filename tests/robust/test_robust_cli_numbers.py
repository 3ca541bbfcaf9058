"""Command-line times and counts that are not finite, negative or zero are exit 3 for
every language, naming the option and the value."""

from __future__ import annotations

from pathlib import Path

import pytest

GDL = Path(__file__).parents[1] / "programs" / "gdl"
PROGRAMS = {
    "hmpl": (["a.hmpl"], {"a__hmpl": 'void main() { Print("hi"); }\n'}),
    "pdl": (["p.pdl"], {"p__pdl": '#long n;\n#task/0;\nn = 1;\nprintl("n=%ld", n);\nhalt;\n'}),
    "gdl": ([str(GDL / "globals.gdl"), str(GDL / "globals.2.gdl")], {}),
}


@pytest.mark.parametrize("language", sorted(PROGRAMS))
@pytest.mark.parametrize(
    ("option", "value"),
    [
        ("--until", "inf"),
        ("--until", "nan"),
        ("--until", "-1"),
        ("--timeout", "nan"),
        ("--timeout", "inf"),
        ("--timeout", "-1"),
    ],
)
def test_a_time_that_is_not_finite_and_non_negative_is_exit_3(cli, language, option, value):
    files, texts = PROGRAMS[language]
    r = cli("run", option, value, *files, **texts)
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.splitlines()[-1] == (
        f"motionvm run: error: argument {option}: '{value}' is not a duration: "
        "a time must be finite and non-negative"
    )


@pytest.mark.parametrize("language", sorted(PROGRAMS))
@pytest.mark.parametrize("every", ["0", "-3"])
def test_scope_every_below_one_is_exit_3(cli, language, every):
    files, texts = PROGRAMS[language]
    channel = {"hmpl": "system_timeInMs", "pdl": "X_vel_max", "gdl": "board.DIAGN$STATUS"}
    argv = ["--scope", channel[language]]
    r = cli("run", *argv, "--scope-out", "x.csv", "--scope-every", every, *files, **texts)
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.strip() == (
        f"motionvm: error: --scope-every must be a whole number of cycles >= 1, got {every}"
    )


@pytest.mark.parametrize("window", ["nan:", "0:inf", ":-1"])
def test_a_scope_window_that_is_not_a_finite_time_is_exit_3(cli, window):
    files, texts = PROGRAMS["hmpl"]
    r = cli(
        "run", "--scope", "system_timeInMs", "--scope-out", "x.csv", "--scope-window", window,
        *files, **texts,
    )  # fmt: skip
    assert (r.code, r.stdout) == (3, "")
    assert r.stderr.startswith(f"motionvm: error: --scope-window '{window}': ")
