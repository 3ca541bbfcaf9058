"""GDL lowering: the generated Python of the example, fault lines, odd procedure names."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from motionvm.lang.gdl import compile_app
from motionvm.lang.gdl.lower import _by_file, emit_python, lower_file
from motionvm.source.diagnostics import DiagnosticSink

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "gdl"
GOLDEN = Path(__file__).resolve().parents[2] / "golden" / "gdl"


def test_gdl_generated_python_of_the_example(monkeypatch: pytest.MonkeyPatch, golden) -> None:
    monkeypatch.chdir(PROGRAMS)
    app = compile_app(["packer.gdl"], sink=DiagnosticSink())
    assert app is not None
    golden(GOLDEN / "packer.py.txt", emit_python(app))


FAULTS = """MODULE m;
  INTEGER$VARIABLE v [ ARRAY$SIZE = 3 ];
  INTEGER$VARIABLE i [ INITIAL$VALUE = 1 ];
  DIGITAL$FLAG go [ ];
  PROCEDURE class;
  DECLARE { STATUS OF go };
  BEGIN
    WHILE VALUE OF i < 10 DO
      VALUE OF i = VALUE OF i + 1;
    END$WHILE;
    VALUE OF v{1} =
      VALUE OF v{2}
      + VALUE OF v{VALUE OF i};
  END$PROCEDURE;
  PROCEDURE lambda;
  DECLARE { STATUS OF go };
  BEGIN
    WHILE VALUE OF v{VALUE OF i - 9} < 1 DO
      VALUE OF v{1} = VALUE OF v{1} / (VALUE OF i - VALUE OF i);
    END$WHILE;
  END$PROCEDURE;
END$MODULE;
"""


def test_gdl_faults_point_at_the_users_line(tmp_path: Path, cli) -> None:
    path = tmp_path / "app.gdl"
    path.write_text(FAULTS)
    scenario = tmp_path / "s.toml"
    scenario.write_text('[[event]]\nat = 0\nset = "STATUS OF go"\nvalue = "ON"\n')
    rc, _out, err = cli("run", path, "--scenario", scenario)
    assert rc == 1
    fault = re.compile(r".*app\.gdl:(\d+:\d+): runtime error in procedure \w+ at t=0\.000 s: (.*)")
    errors = [":".join(m.groups()) for m in map(fault.fullmatch, err.splitlines()) if m]
    assert errors == [
        "13:9:index 10 of v is outside 1..3 (ARRAY$SIZE)",
        "19:37:division by zero",
    ]


def test_gdl_generated_code_uses_only_the_api(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(PROGRAMS)
    for name in ("motion", "all_types", "queue"):
        app = compile_app([f"{name}.gdl"], sink=DiagnosticSink())
        assert app is not None
        text = emit_python(app)
        calls = {part.split("(")[0] for part in text.split("rt.")[1:]}
        assert calls <= {"at", "loop", "read", "assign", "call", "div"}
        for fn in app.functions.values():
            assert fn.__globals__["__builtins__"] == {}


def _deep_whiles(depth: int) -> str:
    loops = "".join(f"WHILE VALUE OF v < {k} DO\n" for k in range(depth))
    return (
        "MODULE deep;\n  INTEGER$VARIABLE v [ ];\n  DIGITAL$FLAG f [ ];\n"
        "  PROCEDURE p;\n  DECLARE { STATUS OF f };\n  BEGIN\n"
        + loops
        + "RETURN;\n"
        + "END$WHILE;\n" * depth
        + "  END$PROCEDURE;\nEND$MODULE;\n"
    )


def test_gdl_every_generated_node_is_built_with_its_location(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """No walk fills in missing locations: each node has all four from the start."""
    monkeypatch.chdir(PROGRAMS)
    apps = [compile_app([f"{name}.gdl"], sink=DiagnosticSink()) for name in ("packer", "all_types")]
    apps.append(compile_app(["d.gdl"], sink=DiagnosticSink(), texts={"d.gdl": _deep_whiles(40)}))
    for app in apps:
        assert app is not None
        for procs in _by_file(app).values():
            for node in ast.walk(lower_file(procs)):
                if "lineno" in node._attributes:
                    assert {"lineno", "col_offset", "end_lineno", "end_col_offset"} <= set(
                        node.__dict__
                    ), ast.dump(node)
