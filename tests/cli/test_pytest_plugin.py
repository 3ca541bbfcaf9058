"""The pytest plugin (cli/pytest_plugin.py), run by pytest in a subprocess: with
`--motionvm` it collects what `motionvm test` does; without it nothing changes."""

from __future__ import annotations

import importlib.metadata
import os
import subprocess
import sys
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from motionvm.cli.cases import collect

REPO = Path(__file__).resolve().parents[2]
OK = 'void main() { Print("ok"); }\n// expect: ok\n'
BAD = 'void main() { Print("bad"); }\n// expect: good\n'
PENDING = BAD + "// pending: not yet\n"
PY_TEST = "def test_python():\n    assert True\n"


def installed() -> bool:
    """Whether the installed motionvm registers the plugin (then no `-p` is needed)."""
    return any(ep.name == "motionvm" for ep in importlib.metadata.entry_points(group="pytest11"))


def pytest_run(*argv: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env.pop("PYTEST_ADDOPTS", None)  # the outer run's options (CI's `-n 2`) are not this run's
    env["PYTHONPATH"] = str(REPO / "src") + os.pathsep + env.get("PYTHONPATH", "")
    plugin = [] if installed() else ["-p", "motionvm.cli.pytest_plugin"]
    return subprocess.run(
        [sys.executable, "-m", "pytest", *plugin, "-p", "no:randomly", *argv],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=240,
    )


@pytest.fixture
def project(tmp_path: Path) -> Path:
    files = {
        "cases/a.hmpl": OK,
        "cases/b.hmpl": BAD,
        "cases/sub/c.hmpl": OK,
        "cases/notes.hmpl": 'void main() { Print("no expectation"); }\n',
        "cases/d.pending.hmpl": OK,  # a companion, no case
        "cases/p.hmpl": PENDING,
        "test_py.py": PY_TEST,
    }
    for name, text in files.items():
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    return tmp_path


def test_the_entry_point_is_declared() -> None:
    meta = tomllib.loads((REPO / "pyproject.toml").read_text())
    assert meta["project"]["entry-points"]["pytest11"] == {"motionvm": "motionvm.cli.pytest_plugin"}


def test_without_the_option_only_python_tests_are_collected(project: Path) -> None:
    r = pytest_run("--collect-only", "-q", cwd=project)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "test_py.py::test_python" in r.stdout and ".hmpl" not in r.stdout


def test_with_the_option_the_cases_of_motionvm_test(project: Path) -> None:
    r = pytest_run("--motionvm", "--collect-only", "-q", cwd=project)
    ids = sorted(line.split("::")[0] for line in r.stdout.splitlines() if ".hmpl::" in line)
    old = os.getcwd()
    os.chdir(project)
    try:
        expected = sorted(c.id for c in collect(["cases"]))
    finally:
        os.chdir(old)
    assert ids == expected == ["cases/a.hmpl", "cases/b.hmpl", "cases/p.hmpl", "cases/sub/c.hmpl"]


def test_a_run_with_k_junitxml_and_last_failed(project: Path) -> None:
    r = pytest_run(
        "--motionvm", "cases", "-k", "not sub", "--junitxml", "report.xml", "-rA", cwd=project
    )
    assert r.returncode == 1, r.stdout + r.stderr
    assert "1 failed, 1 passed, 1 deselected, 1 xfailed" in r.stdout
    assert "expected stdout" in r.stdout and "+bad" in r.stdout  # the case's diff
    suite = ET.parse(project / "report.xml").getroot().find("testsuite")
    assert suite.get("tests") == "3" and suite.get("failures") == "1"
    r = pytest_run("--motionvm", "cases", "--lf", cwd=project)
    assert "rerun previous 1 failure" in r.stdout and " 1 failed in " in r.stdout, r.stdout
