"""GDL RTS: determinism, jumping the clock, forcing, runaway activations, scenario errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.gdl import compile_app
from motionvm.lang.gdl import rts as rts_module
from motionvm.lang.gdl.app import App
from motionvm.lang.gdl.rts import Rts, format_time
from motionvm.runtime.clock import Clock
from motionvm.source.diagnostics import DiagnosticSink

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "gdl"

TOGGLE = """MODULE m;
  DIGITAL$FLAG flip [ ];
  DIGITAL$VARIABLE memo [ ];
  IO$BOARD io [ SLOT = 1 ];
  DIGITAL$INPUT go [ BOARD$NAME = io, CHANNEL = 1 ];
  PROCEDURE loop;
  DECLARE { STATUS OF flip, STATUS OF go };
  BEGIN
    STATUS OF flip = NOT STATUS OF flip;
  END$PROCEDURE;
END$MODULE;
"""


def _run_toggle(cli, *argv) -> tuple[int, str]:
    """`motionvm run TOGGLE-FILE ARGV...`: (exit code, stdout and stderr in the order
    written, after the compile warning every run of TOGGLE starts with)."""
    rc, out, _ = cli("run", *argv, merged=True)
    warning, source, caret, rest = out.split("\n", 3)
    assert warning.endswith(
        ":9:5: warning: procedure loop assigns STATUS OF flip, one of its own activators: "
        "a change runs it once more"
    )
    assert (source.strip(), caret.strip()) == ("STATUS OF flip = NOT STATUS OF flip;", "^")
    return rc, rest


def _gdl(tmp_path: Path, text: str) -> str:
    path = tmp_path / "app.gdl"
    path.write_text(text)
    return str(path)


def _app(tmp_path: Path, text: str) -> App:
    sink = DiagnosticSink()
    app = compile_app([_gdl(tmp_path, text)], sink=sink)
    assert app is not None, [d.headline() for d in sink.items]
    return app


def _scenario(tmp_path: Path, text: str) -> str:
    path = tmp_path / "s.toml"
    path.write_text(text)
    return str(path)


def test_gdl_time_format_is_exact() -> None:
    assert [format_time(c) for c in (0, 1, 999, 1000, 123456)] == [
        "0.000",
        "0.001",
        "0.999",
        "1.000",
        "123.456",
    ]
    assert [format_time(c, 0.0005) for c in (0, 1, 3, 2001)] == [
        "0.0000",
        "0.0005",
        "0.0015",
        "1.0005",
    ]
    assert format_time(10**9 + 1, 0.001) == "1000000.001"
    assert format_time(3, 0.002) == "0.006"
    assert format_time(7, 0.3 / 1000) == "0.0021"  # 0.00030000000000000003 is 3/10000


@pytest.mark.parametrize("name", ["motion", "packer", "queue"])
def test_gdl_jumping_the_clock_equals_stepping(
    name: str, monkeypatch: pytest.MonkeyPatch, jumped_and_stepped
) -> None:
    monkeypatch.chdir(PROGRAMS)
    jumped, stepped = jumped_and_stepped([f"{name}.gdl"], f"{name}.toml")
    assert jumped == stepped
    assert jumped[0]


def test_gdl_runs_are_deterministic(monkeypatch: pytest.MonkeyPatch, cli) -> None:
    monkeypatch.chdir(PROGRAMS)
    runs = [cli("run", "motion.gdl", "--scenario", "motion.toml", merged=True) for _ in range(2)]
    assert runs[0] == runs[1]


def test_gdl_runaway_activations_are_stopped(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, cli
) -> None:
    monkeypatch.setattr(rts_module, "MAX_RUNS_PER_CYCLE", 3)
    path = _gdl(tmp_path, TOGGLE)
    s = _scenario(
        tmp_path,
        '[[event]]\nat = 0.5\nset = "STATUS OF go"\nvalue = "ON"\n'
        '[[event]]\nat = 0.6\nset = "STATUS OF go"\nvalue = "OFF"\n',
    )
    rc, out = _run_toggle(cli, path, "--scenario", s)  # faults among messages
    assert rc == 1
    lines = out.splitlines()
    assert lines[:4] == [
        "t=0.500 input STATUS OF go = ON",
        "t=0.500 run loop",
        "t=0.500 set STATUS OF flip = ON",
        "t=0.500 run loop",
    ]
    assert lines[7].endswith(
        "runtime error in procedure loop at t=0.500 s: more than 3 procedure runs in one "
        "cycle: procedures keep triggering each other (ready queue cleared)"
    )
    assert lines[8] == "t=0.600 input STATUS OF go = OFF"


def test_gdl_force_api_and_release(tmp_path: Path) -> None:
    app = _app(tmp_path, TOGGLE)
    lines: list[str] = []
    rts = Rts(app, Clock(0.001), lines.append, lines.append)
    flip, memo, go = (app.objects[k] for k in ("flip", "memo", "go"))
    rts.force(memo, "VALUE", 0, True)
    rts.write(memo, "VALUE", 0, False, "set")
    assert rts.read(memo, "VALUE", 0) is True
    rts.release(memo, "VALUE", 0)
    assert rts.read(memo, "VALUE", 0) is False
    rts.force(go, "STATUS", 0, True)
    assert list(rts.ready) == [app.procedures[0]]
    assert flip.type.state("STATUS").forceable
    assert lines == [
        "t=0.000 force VALUE OF memo = ON",
        "t=0.000 release VALUE OF memo = OFF",
        "t=0.000 force STATUS OF go = ON",
    ]


def test_gdl_force_refuses_variables_without_f(tmp_path: Path) -> None:
    app = _app(
        tmp_path,
        TOGGLE.replace("DIGITAL$VARIABLE memo [ ];", "INTEGER$CONSTANT memo [ VALUE = 1 ];"),
    )
    rts = Rts(app, Clock(0.001), print, print)
    with pytest.raises(ValueError, match="VALUE of INTEGER\\$CONSTANT cannot be forced"):
        rts.force(app.objects["memo"], "VALUE", 0, 2)


def test_gdl_force_from_the_command_line(tmp_path: Path, cli) -> None:
    path = _gdl(tmp_path, TOGGLE)
    rc, out, _ = cli("run", path, "--until", 0.01, "--force", "STATUS OF flip = ON")
    assert rc == 0
    assert out.splitlines() == ["t=0.000 force STATUS OF flip = ON", "t=0.000 run loop"]
    rc, _, err = cli("run", path, "--until", 0.01, "--force", "VALUE OF memo")
    assert rc == 3
    assert "write --force 'KEYWORD OF object = value'" in err


def test_gdl_until_ends_the_run(tmp_path: Path, cli) -> None:
    path = _gdl(tmp_path, TOGGLE)
    s = _scenario(
        tmp_path, 'until = 0.2\n[[event]]\nat = 0.3\nset = "VALUE OF memo"\nvalue = "ON"\n'
    )
    # the run ends at the scenario's `until`; the event after it is named on stderr
    assert _run_toggle(cli, path, "--scenario", s) == (
        0,
        "motionvm: note: the GDL scenario (1 event not applied yet, the next at t=0.300) "
        "still ran when the run ended at t=0.2 s\n",
    )
    assert _run_toggle(cli, path, "--scenario", s, "--until", 0.3) == (
        0,
        "t=0.300 input VALUE OF memo = ON\n",
    )


@pytest.mark.parametrize(
    ("toml", "place", "message"),
    [
        ("[[event]\n", "1:8", "not valid TOML"),
        ("speed = 3\n", "1:1", "unknown key 'speed'"),
        (
            '[[event]]\nat = 0.1\nset = "STATUS OF gone"\nvalue = "ON"\n',
            "3:1",
            "event 1: unknown object 'gone'",
        ),
        (
            '[[event]]\nat = 0.1\nset = "STATUS OF go"\nvalue = 3\n',
            "4:1",
            "event 1: STATUS OF go takes ON or OFF, not 3",
        ),
        (
            '[[event]]\nat = 0.1\nset = "STATUS OF go{2}"\nvalue = "ON"\n',
            "3:1",
            "event 1: index 2 of go is outside none: it is not an array",
        ),
        (
            '[[event]]\nat = 0.1\nset = "SPEED OF go"\nvalue = "ON"\n',
            "3:1",
            "event 1: DIGITAL$INPUT has no state variable SPEED",
        ),
        ('[[event]]\nat = 0.1\nforce = "DIAGN$STATUS OF io"\nvalue = "FAULT"\n', "", ""),
        (
            '[[event]]\nat = -1\nset = "STATUS OF go"\nvalue = "ON"\n',
            "2:1",
            "event 1: 'at' must be a number of seconds >= 0, not -1",
        ),
        (
            '[[event]]\nat = 0.1\nset = "STATUS OF go"\nvalue = "ON"\nduring = "loop"\n',
            "5:1",
            "event 1: 'during' and 'line' go together",
        ),
        (
            '[[event]]\nat = 0.1\nset = "STATUS OF go"\nvalue = "ON"\nduring = "nope"\nline = 3\n',
            "5:1",
            "event 1: unknown procedure 'nope'",
        ),
        (
            '[[event]]\nat = 0.1\nset = "STATUS OF go"\nforce = "STATUS OF go"\nvalue = "ON"\n',
            "4:1",
            "event 1: give exactly one of set, force, release",
        ),
        ('[initial]\n"STATUS go" = "ON"\n', "2:1", "'STATUS go' is not 'KEYWORD OF object'"),
        (
            '[[event]]\nat = 0\nforce = "DIAGN$STATUS OF io"\nvalue = "BROKEN"\n',
            "4:1",
            "event 1: DIAGN$STATUS OF io takes one of NO$FAULT, FAULT, not 'BROKEN'",
        ),
        (
            '[[event]]\nat = 0\nrelease = "VALUE OF memo"\nline = 2\n',
            "4:1",
            "event 1: 'during' and 'line' go together",
        ),
    ],
)
def test_gdl_bad_scenarios_exit_3(tmp_path: Path, toml: str, place: str, message: str, cli) -> None:
    path = _gdl(tmp_path, TOGGLE)
    scenario = _scenario(tmp_path, toml)
    rc, out, _ = cli("run", path, "--scenario", scenario, merged=True)
    if not message:  # DIAGN$STATUS of IO$BOARD has access rf: forcing is allowed
        assert rc == 0
        return
    assert rc == 3
    errors = [line for line in out.splitlines() if line.startswith(scenario)]
    assert len(errors) == 1, out
    assert errors[0].startswith(f"{scenario}:{place}: error: ") and message in errors[0], out


def test_gdl_scenario_refuses_to_force_rw(tmp_path: Path, cli) -> None:
    path = _gdl(
        tmp_path,
        TOGGLE.replace(
            "IO$BOARD io [ SLOT = 1 ];",
            "IO$BOARD io [ SLOT = 1 ];\n  DC$MOTOR$AXIS motor [ AXIS$NUMBER = 1 ];",
        ),
    )
    s = _scenario(
        tmp_path, '[[event]]\nat = 0\nforce = "CONSTANT$STATUS OF motor"\nvalue = "ENABLED"\n'
    )
    rc, out, _ = cli("run", path, "--scenario", s, merged=True)
    assert rc == 3
    assert "CONSTANT$STATUS of DC$MOTOR$AXIS cannot be forced (access rw, no 'f')" in out


def test_gdl_scenario_refuses_to_change_a_constant(tmp_path: Path, cli) -> None:
    path = _gdl(
        tmp_path,
        TOGGLE.replace("DIGITAL$VARIABLE memo [ ];", "INTEGER$CONSTANT memo [ VALUE = 1 ];"),
    )
    s = _scenario(tmp_path, '[[event]]\nat = 0\nset = "VALUE OF memo"\nvalue = 2\n')
    rc, out, _ = cli("run", path, "--scenario", s, merged=True)
    assert rc == 3
    assert "memo is an INTEGER$CONSTANT: it never changes" in out


FOLLOWERS = """MODULE f;
  MACHINE plant [ ];
  DC$MOTOR$AXIS spindle [ AXIS$NUMBER = 1 ];
  ABSOLUTE$ENCODER spindle_encoder [ ENCODER$NUMBER = 1, AXIS$NAME = spindle ];
  PROCEDURE mode;
  DECLARE { OPERATING$MODE OF plant };
  BEGIN
    IF OPERATING$MODE OF plant = AUTOMATIC THEN
      CONSTANT$STATUS OF spindle = ENABLED;
      RUN$AT$SPEED OF spindle (1000);
    ELSE
      CONSTANT$STATUS OF spindle = DISABLED;
    END$IF;
  END$PROCEDURE;
  PROCEDURE watch;
  DECLARE { OPERATING$CONDITION OF spindle_encoder };
  BEGIN
    RETURN;
  END$PROCEDURE;
END$MODULE;
"""


def test_gdl_followers_update_the_same_when_the_clock_jumps(
    tmp_path: Path, jumped_and_stepped
) -> None:
    path = _gdl(tmp_path, FOLLOWERS)
    s = _scenario(
        tmp_path,
        '[[event]]\nat = 0.1\nset = "OPERATING$MODE OF plant"\nvalue = "AUTOMATIC"\n'
        '[[event]]\nat = 0.5\nset = "OPERATING$MODE OF plant"\nvalue = "MANUAL"\n',
    )
    jumped, stepped = jumped_and_stepped([path], s)
    assert jumped == stepped
    assert "t=0.501 update OPERATING$CONDITION OF spindle_encoder = STOPPED" in jumped[0]
    until = jumped_and_stepped([path], s, until=0.3)
    assert until[0] == until[1] and until[0][2] == 301


def test_gdl_shuffled_order_of_shared_activators(monkeypatch: pytest.MonkeyPatch, cli) -> None:
    monkeypatch.chdir(PROGRAMS)
    orders = set()
    argv = ("run", "queue.gdl", "--scenario", "queue.toml", "--shuffle-order")
    for seed in range(8):
        rc, out, _ = cli(*argv, seed, merged=True)
        assert rc == 0
        lines = out.splitlines()
        at_30 = [line for line in lines if line.startswith("t=0.030 run ")]
        orders.add(tuple(at_30))
        assert cli(*argv, seed, merged=True) == (rc, out, "")
    assert orders == {
        ("t=0.030 run procedure_1", "t=0.030 run procedure_2"),
        ("t=0.030 run procedure_2", "t=0.030 run procedure_1"),
    }
