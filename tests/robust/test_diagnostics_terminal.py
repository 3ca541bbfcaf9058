"""Compile messages as a person reads them: in the order of the file, coloured on a
terminal (never in a pipe or with NO_COLOR), a "did you mean" for misspelt names of
every kind, several syntax errors of one file in one pass."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
from pathlib import Path

import pytest

from motionvm.source.diagnostics import Diagnostic, in_order
from motionvm.source.files import SourcePos
from motionvm.source.suggest import closest

MISTAKES = """int f() {
    int unused1;
    return zz;
}
void main() {
    int cnt = 0;
    int unused2;
    cout = 3;
    Print("%d", cnt);
}
"""
ESC = b"\x1b["


def _stderr_on_terminal(argv, cwd: Path, env: dict[str, str]) -> bytes:
    primary, secondary = pty.openpty()
    proc = subprocess.Popen(
        [sys.executable, "-m", "motionvm", *argv],
        cwd=cwd,
        stdout=subprocess.DEVNULL,
        stderr=secondary,
        env={**{k: v for k, v in os.environ.items() if k != "NO_COLOR"}, **env},
    )
    os.close(secondary)
    chunks = []
    while True:
        try:
            data = os.read(primary, 4096)
        except OSError:  # EIO: the child closed its end
            break
        if not data:
            break
        chunks.append(data)
    os.close(primary)
    proc.wait(timeout=60)
    return b"".join(chunks)


@pytest.fixture
def mistakes(tmp_path) -> Path:
    (tmp_path / "d.hmpl").write_text(MISTAKES)
    return tmp_path


def _env() -> dict[str, str]:
    return {"PYTHONPATH": os.pathsep.join(sys.path), "TERM": "xterm-256color"}


def test_messages_are_coloured_on_a_terminal(mistakes):
    err = _stderr_on_terminal(["check", "d.hmpl"], mistakes, _env())
    assert b"\x1b[1;31merror" in err, err
    assert b"\x1b[1;35mwarning" in err, err
    assert b"\x1b[1md.hmpl:8:5\x1b[0m" in err, err


def test_no_color_takes_the_colour_out(mistakes):
    err = _stderr_on_terminal(["check", "d.hmpl"], mistakes, {**_env(), "NO_COLOR": "1"})
    assert ESC not in err
    assert b"d.hmpl:8:5: error: 'cout' undeclared (did you mean 'cnt'?)" in err


def test_a_pipe_gets_no_colour(cli):
    r = cli("check", "d.hmpl", d__hmpl=MISTAKES)
    assert "\x1b[" not in r.stderr
    heads = [line.split(": ")[0] for line in r.stderr.splitlines() if line.startswith("d.hmpl:")]
    assert heads == ["d.hmpl:2:9", "d.hmpl:3:12", "d.hmpl:7:9", "d.hmpl:8:5"]


def _d(file: str, line: int, col: int, severity: str = "error") -> Diagnostic:
    return Diagnostic(SourcePos(file, line, col), f"m{line}", severity)


def test_in_order_sorts_each_file_and_keeps_notes_with_their_message():
    given = [
        _d("a", 7, 9, "warning"),
        _d("a", 3, 10),
        _d("a", 1, 1, "note"),  # belongs to the error at 3:10
        _d("b", 2, 1),
        _d("a", 3, 2),
    ]
    assert in_order(given) == [given[4], given[1], given[2], given[0], given[3]]


@pytest.mark.parametrize(
    ("typed", "names", "meant"),
    [
        ("cout", ["cnt", "count_max", "Print"], "cnt"),
        ("slep", ["sleep", "wait", "halt"], "sleep"),
        ("mian_motor", ["main_motor", "cooling_fan"], "main_motor"),
        ("xyz", ["abc", "Print"], None),
        ("ab", ["ac"], None),  # too short to guess
    ],
)
def test_closest_handles_short_names(typed, names, meant):
    assert closest(typed, names) == meant


def test_a_misspelt_pdl_keyword_is_suggested(cli):
    r = cli("check", "k.pdl", k__pdl="#long x;\n#task/0;\nx = 1;\nslep(5);\nhalt;\n")
    assert r.code == 2
    assert "(did you mean 'sleep'?)" in r.stderr


def test_three_syntax_errors_in_one_pass(cli):
    text = 'void main() {\n    int a = 1 +;\n    int b = 2;\n    b = (3 * ;\n    Print("%d", a b);\n    a = 4;\n}\n'
    r = cli("check", "e.hmpl", e__hmpl=text)
    heads = [line.split(": error")[0] for line in r.stderr.splitlines() if ": error" in line]
    assert heads == ["e.hmpl:2:16", "e.hmpl:4:14", "e.hmpl:5:19"], r.stderr


GDL_THREE = """MODULE m;
  DIGITAL$FLAG f [ INITIAL$VALUE = OFF ];
  INTEGER$VARIABLE v [ INITIAL$VALUE = 0 ];
  PROCEDURE p1;
  DECLARE { STATUS OF f };
  BEGIN
    VALUE OF v = (1 + ;
    STATUS OF f = ON;
  END$PROCEDURE;
  PROCEDURE p2;
  DECLARE { STATUS OF f };
  BEGIN
    IF STATUS OF f = ON THEN
      VALUE OF v = 2 * * 3;
    END$IF;
  END$PROCEDURE;
  PROCEDURE p3;
  DECLARE { STATUS OF f };
  BEGIN
    VALUE OF v = 3
    STATUS OF f = OFF;
  END$PROCEDURE;
END$MODULE;
"""


@pytest.mark.parametrize(
    ("name", "text", "expected"),
    [
        ("e.gdl", GDL_THREE, ["e.gdl:7:23", "e.gdl:14:24", "e.gdl:20:19"]),
        (
            "e.pdl",
            "#long x;\n#task/0;\nx = (1 + ;\nx = 2;\nx = 3 * * 4;\nx = 5;\nif (x > ) x = 1;\nhalt;\n",
            ["e.pdl:3:5", "e.pdl:5:11", "e.pdl:7:9"],
        ),
    ],
)
def test_three_syntax_errors_in_one_pass_in_pdl_and_gdl(cli, name, text, expected):
    r = cli("check", name, **{name.replace(".", "__"): text})
    heads = [line.split(": error")[0] for line in r.stderr.splitlines() if ": error" in line]
    assert heads == expected, r.stderr
