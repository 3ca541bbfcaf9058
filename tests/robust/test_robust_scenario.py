"""Scenario times that are not finite or negative are exit 3 naming key and value."""

from __future__ import annotations

from pathlib import Path

import pytest

PROGRAMS = Path(__file__).parents[1] / "programs" / "gdl"


def run(cli, scenario: str):
    app = [str(PROGRAMS / "globals.gdl"), str(PROGRAMS / "globals.2.gdl")]
    return cli("run", "--scenario", "s.toml", *app, s__toml=scenario)


EVENT = '[[event]]\nat = {}\nset = "DIAGN$STATUS OF m2"\nvalue = "FAULT"\n'


@pytest.mark.parametrize("at", ["nan", "inf", "-inf", "-0.5"])
def test_a_bad_event_time_is_exit_3(cli, at):
    r = run(cli, EVENT.format(at))
    assert r.code == 3
    want = f"s.toml:2:1: error: event 1: 'at' must be a number of seconds >= 0, not {float(at)!r}"
    assert r.stderr.splitlines()[0] == want


@pytest.mark.parametrize("until", ["nan", "inf", "-inf", "-1.0"])
def test_a_bad_until_is_exit_3(cli, until):
    r = run(cli, f"until = {until}\n")
    assert r.code == 3
    want = f"s.toml:1:1: error: 'until' must be a number of seconds >= 0, not {float(until)!r}"
    assert r.stderr.splitlines()[0] == want


def test_a_good_scenario_still_runs(cli):
    r = run(cli, "until = 0.05\n" + EVENT.format("0.01"))
    assert r.code == 0 and "run watch_b" in r.stdout
