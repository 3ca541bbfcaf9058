"""The golden GDL programs as a whole: together they use every object type, and every
stage of `motionvm dump` shows one of them. (Each program's own expectations are checked
by the runner of all golden programs, tests/programs/test_programs.py.)"""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.gdl.compiler import compile_app
from motionvm.lang.gdl.objects import TYPES
from motionvm.source.diagnostics import DiagnosticSink

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "gdl"


def _primaries(folder: Path) -> list[Path]:
    return sorted(p for p in folder.glob("*.gdl") if "." not in p.stem)


def _app_files(primary: Path) -> list[str]:
    more = sorted(
        primary.parent.glob(f"{primary.stem}.*.gdl"), key=lambda p: int(p.name.split(".")[1])
    )
    return [primary.name] + [p.name for p in more]


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
