"""A scenario of thousands of events loads in time linear in its size: the place of each
event's key is found by reading that event's lines only, and a name no variable of the
machine knows (a GDL object's `KW OF name`) costs no comparison with every channel name."""

from __future__ import annotations

import difflib
from pathlib import Path

from motionvm.source import toml_places

PROGRAMS = Path(__file__).parents[1] / "programs" / "gdl"
HMPL = 'void main(void) {\n    Sleep(5);\n    Print("t=%d", system_ltest0);\n}\n'


def events(n: int, name: str, values: tuple[str, ...]) -> str:
    return "".join(
        f'[[event]]\nat = {i * 1e-6:.6f}\nset = "{name}"\nvalue = {values[i % len(values)]}\n\n'
        for i in range(n)
    )


def count_calls(monkeypatch, module, name: str) -> list[int]:
    calls = [0]
    original = getattr(module, name)

    def counted(*args, **kwargs):
        calls[0] += 1
        return original(*args, **kwargs)

    monkeypatch.setattr(module, name, counted)
    return calls


def test_each_line_of_a_big_scenario_is_looked_at_once(cli, monkeypatch):
    n = 400
    text = events(n, "system_ltest0", ("1", "2"))
    looked_at = count_calls(monkeypatch, toml_places, "_header")
    r = cli("run", "--scenario", "s.toml", "p.hmpl", p__hmpl=HMPL, s__toml=text)
    assert r.code == 0, r.stderr
    assert r.stdout == "t=2\n"
    assert looked_at[0] <= len(text.splitlines())  # was n * lines / 2: 400 times as many


def test_many_bad_events_are_each_placed_at_their_own_key(cli, monkeypatch):
    n = 300
    text = events(n, "system_ltest0", ("[1]",))
    looked_at = count_calls(monkeypatch, toml_places, "_header")
    r = cli("run", "--scenario", "s.toml", "p.hmpl", p__hmpl=HMPL, s__toml=text)
    assert r.code == 3
    lines = r.stderr.splitlines()
    assert len(lines) == n
    assert lines[-1].startswith(f"s.toml:{5 * n - 1}:1: error: event {n}: value = [1]")
    assert looked_at[0] <= len(text.splitlines())


def test_gdl_events_cost_no_suggestion_search(cli, monkeypatch):
    n = 50
    text = events(n, "DIAGN$STATUS OF m2", ('"FAULT"', '"NO$FAULT"'))
    searches = count_calls(monkeypatch, difflib, "get_close_matches")
    app = [str(PROGRAMS / "globals.gdl"), str(PROGRAMS / "globals.2.gdl")]
    r = cli("run", "--until", "0.01", "--scenario", "s.toml", *app, s__toml=text)
    assert r.code == 0, r.stderr
    assert "input DIAGN$STATUS OF m2 = FAULT" in r.stdout
    assert searches[0] == 0  # was one search through ~1,600 channel names per event
