"""Golden GDL programs: run applications against scenarios, and compile-error files.

Layout of `tests/programs/gdl/`:
- `NAME.gdl` (+ `NAME.2.gdl`, `NAME.3.gdl`, ... linked after it) with `NAME.toml` (the
  scenario, optional) and `NAME.out`: stdout and stderr of the run, then `exit N`.
- `errors/NAME.gdl` (+ `NAME.2.gdl` ...): comments `| error: LINE:COL: MESSAGE |` and
  `| warning: LINE:COL: MESSAGE |` list every diagnostic of that file, exactly.

`GDL_REGEN=1 python -m pytest tests/lang/gdl` rewrites the `.out` files; review the diff.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.objects import TYPES
from motionvm.source.diagnostics import DiagnosticSink

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "gdl"
EXPECT = re.compile(r"\|\s*(error|warning): (\d+):(\d+): ([^|]*?)\s*\|")


def _primaries(folder: Path) -> list[Path]:
    return sorted(p for p in folder.glob("*.gdl") if "." not in p.stem)


def _app_files(primary: Path) -> list[str]:
    more = sorted(
        primary.parent.glob(f"{primary.stem}.*.gdl"), key=lambda p: int(p.name.split(".")[1])
    )
    return [primary.name] + [p.name for p in more]


def _run(cli, primary: Path) -> str:
    """`motionvm run` of the application: stdout and stderr in the order written, `exit N`."""
    scenario = primary.with_suffix(".toml")
    argv = ["run", *_app_files(primary)]
    if scenario.exists():
        argv += ["--scenario", scenario.name]
    rc, out, _ = cli(*argv, merged=True)
    return out + f"exit {rc}\n"


@pytest.mark.parametrize("primary", _primaries(PROGRAMS), ids=lambda p: p.stem)
def test_gdl_program_output(primary: Path, monkeypatch: pytest.MonkeyPatch, cli) -> None:
    monkeypatch.chdir(PROGRAMS)
    got = _run(cli, primary)
    expected = primary.with_suffix(".out")
    if os.environ.get("GDL_REGEN"):
        expected.write_text(got)
    assert got == expected.read_text()


@pytest.mark.parametrize("primary", _primaries(PROGRAMS / "errors"), ids=lambda p: p.stem)
def test_gdl_compile_errors(primary: Path, monkeypatch: pytest.MonkeyPatch, cli) -> None:
    monkeypatch.chdir(primary.parent)
    files = _app_files(primary)
    expected = []
    for name in files:
        for m in EXPECT.finditer(Path(name).read_text()):
            expected.append((name, int(m[2]), int(m[3]), m[1], " ".join(m[4].split())))
    assert expected, f"{primary.name} lists no expected diagnostic"
    sink = DiagnosticSink()
    assert compile_app(files, sink=sink) is None
    got = [(d.pos.file, d.pos.line, d.pos.col, d.severity, d.message) for d in sink.items]
    assert sorted(got) == sorted(expected)
    rc, _out, err = cli("check", *files)
    assert rc == 2
    assert "Traceback" not in err


def test_gdl_run_programs_cover_every_object_type(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(PROGRAMS)
    seen: set[str] = set()
    for primary in _primaries(PROGRAMS):
        app = compile_app(_app_files(primary), sink=DiagnosticSink())
        assert app is not None
        seen |= {o.type.name for o in app.objects.values()}
    assert seen == {t.name for t in TYPES}


@pytest.mark.parametrize("stage", ["tokens", "ast", "py"])
def test_gdl_dump_stages(stage: str, monkeypatch: pytest.MonkeyPatch, cli) -> None:
    monkeypatch.chdir(PROGRAMS)
    rc, out, err = cli("dump", "--stage", stage, "queue.gdl")
    assert rc == 0
    assert err == "" and out
    assert cli("dump", "--stage", "bytecode", "queue.gdl")[0] == 3
