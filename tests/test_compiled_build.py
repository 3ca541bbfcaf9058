"""The optional compiled build of the motion cycle (motionvm/compiled_build.py): when it
is used, when the pure-Python modules are, and that both give the same runs byte for
byte."""

from __future__ import annotations

import importlib.machinery
import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

import pytest

from motionvm import compiled_build as cb

SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]


def _package(tmp_path: Path, built: bool = True) -> Path:
    """A package tree with the compiled modules' sources, their extensions (empty files:
    only their presence counts) and the build's record."""
    root = tmp_path / "motionvm"
    record = {}
    for m, f in cb.sources(root).items():
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(f"# {m}\n", encoding="utf-8")
        f.with_suffix(".pxd").write_text("# types\n", encoding="utf-8")
        if built:
            f.with_name(f.stem + SUFFIX).write_bytes(b"")
        record[m] = cb.source_digest(f)
    if built:
        (root / cb.RECORD).write_text(json.dumps(record), encoding="utf-8")
    return root


def test_a_fresh_build_is_used(tmp_path):
    assert cb.why_pure(_package(tmp_path), environ={}) is None


def test_no_build_is_pure_python_without_a_reason(tmp_path):
    assert cb.why_pure(_package(tmp_path, built=False), environ={}) == ""


def test_an_edited_source_or_its_types_make_the_build_stale(tmp_path):
    root = _package(tmp_path)
    f = cb.sources(root)["motionvm.motion.axis_cycle"]
    f.write_text("# edited\n", encoding="utf-8")
    reason = cb.why_pure(root, environ={})
    assert "motionvm/motion/axis_cycle.py changed since it was compiled" in reason
    root = _package(tmp_path / "b")
    cb.sources(root)["motionvm.drives.cia402"].with_suffix(".pxd").write_text("#", "utf-8")
    assert "motionvm/drives/cia402.py changed" in cb.why_pure(root, environ={})


def test_an_extension_without_its_source_is_used(tmp_path):
    root = _package(tmp_path)
    cb.sources(root)["motionvm.motion.profile"].unlink()
    assert cb.why_pure(root, environ={}) is None
    assert cb.why_pure(root, environ={"MOTIONVM_PURE": "1"}) is None  # nothing to fall back to


def test_half_a_build_a_missing_record_or_motionvm_pure_are_pure(tmp_path):
    root = _package(tmp_path)
    assert cb.why_pure(root, environ={"MOTIONVM_PURE": "1"}) == "MOTIONVM_PURE is set"
    assert cb.why_pure(root, environ={"MOTIONVM_PURE": "0"}) is None
    (root / cb.RECORD).unlink()
    assert "missing or unreadable" in cb.why_pure(root, environ={})
    root = _package(tmp_path / "b")
    f = cb.sources(root)["motionvm.motion.profile"]
    f.with_name(f.stem + SUFFIX).unlink()
    assert cb.why_pure(root, environ={}) == "the compiled build is incomplete"


BUILD = cb.build_description("3.1.8")


def _recorded(root: Path, build: str | None = BUILD) -> Path:
    """`root` with a record that says how the build was made (setup.py's description)."""
    record = json.loads((root / cb.RECORD).read_text(encoding="utf-8"))
    if build is not None:
        record[cb.BUILD_KEY] = build
    (root / cb.RECORD).write_text(json.dumps(record), encoding="utf-8")
    return root


def test_a_build_of_the_same_sources_made_the_same_way_is_reused(tmp_path):
    root = _recorded(_package(tmp_path))
    assert cb.reusable(root, BUILD, SUFFIX)
    assert cb.why_pure(root, environ={}) is None  # the build key is no module
    assert not cb.reusable(root, cb.build_description("3.2.0"), SUFFIX)  # another Cython
    assert not cb.reusable(root, BUILD, ".cpython-399-other.so")  # another Python
    assert not cb.reusable(_recorded(_package(tmp_path / "old"), None), BUILD, SUFFIX)
    root = _recorded(_package(tmp_path / "edited"))
    cb.sources(root)["motionvm.motion.axis_cycle"].with_suffix(".pxd").write_text("#", "utf-8")
    assert not cb.reusable(root, BUILD, SUFFIX)
    root = _recorded(_package(tmp_path / "half"))
    f = cb.sources(root)["motionvm.drives.sensors"]
    f.with_name(f.stem + SUFFIX).unlink()
    assert not cb.reusable(root, BUILD, SUFFIX)
    root = _recorded(_package(tmp_path / "norecord"))
    (root / cb.RECORD).write_text("{", encoding="utf-8")
    assert not cb.reusable(root, BUILD, SUFFIX)
    assert not cb.reusable(_package(tmp_path / "nobuild", built=False), BUILD, SUFFIX)


def test_after_one_edited_module_only_that_one_is_compiled_again(tmp_path):
    root = _recorded(_package(tmp_path))
    record = json.loads((root / cb.RECORD).read_text(encoding="utf-8"))
    assert cb.reusable_modules(root, BUILD, SUFFIX) == set()  # a record without declarations
    record[cb.DECLARATIONS_KEY] = cb.declarations_digest(root)
    (root / cb.RECORD).write_text(json.dumps(record), encoding="utf-8")
    assert cb.reusable_modules(root, BUILD, SUFFIX) == set(cb.MODULES)
    assert cb.reusable_modules(root, cb.build_description("3.2.0"), SUFFIX) == set()
    files = cb.sources(root)
    files["motionvm.motion.profile"].write_text("# edited\n", encoding="utf-8")
    assert cb.reusable_modules(root, BUILD, SUFFIX) == set(cb.MODULES) - {"motionvm.motion.profile"}
    # a .pxd is cimported by other modules: every module is compiled again
    files["motionvm.drives.sensors"].with_suffix(".pxd").write_text("# new types\n", "utf-8")
    assert cb.reusable_modules(root, BUILD, SUFFIX) == set()


FAKE_CYTHON = """__version__ = "3.1.8"
"""
FAKE_CYTHON_BUILD = """def cythonize(extensions, **options):
    return extensions
"""


def _setup_tree(tmp_path: Path) -> Path:
    """A project with the repository's setup.py and compiled_build.py, placeholder
    sources and extensions of the compiled modules, and a stand-in for Cython that
    translates nothing (a compile attempt fails: the C compiler gets .py files)."""
    repo = Path(__file__).resolve().parents[1]
    project = tmp_path / "project"
    root = _recorded(_package(project / "src"))
    (root / "__init__.py").write_text("", encoding="utf-8")
    for sub in ("drives", "motion"):
        (root / sub / "__init__.py").write_text("", encoding="utf-8")
    (root / "compiled_build.py").write_bytes((repo / "src/motionvm/compiled_build.py").read_bytes())
    (project / "setup.py").write_bytes((repo / "setup.py").read_bytes())
    (project / "setup.cfg").write_text("[options]\npackage_dir =\n    =src\n", encoding="utf-8")
    fake = tmp_path / "fake" / "Cython"
    (fake / "Build").mkdir(parents=True)
    (fake / "__init__.py").write_text(FAKE_CYTHON, encoding="utf-8")
    (fake / "Build" / "__init__.py").write_text(FAKE_CYTHON_BUILD, encoding="utf-8")
    return project


def _setup(project: Path, *args: str) -> str:
    env = dict(os.environ, PYTHONPATH=str(project.parent / "fake"))
    env.pop("MOTIONVM_PURE", None)
    r = subprocess.run([sys.executable, "setup.py", *args], cwd=project, env=env,
                       capture_output=True, text=True, timeout=120, check=True)  # fmt: skip
    return r.stderr


@pytest.mark.skipif(SUFFIX != sysconfig.get_config_var("EXT_SUFFIX"), reason="another ABI")
def test_setup_reuses_a_current_build_and_says_when_it_compiles(tmp_path):
    pytest.importorskip("setuptools")  # (a venv of Python 3.12 or later has none)
    project = _setup_tree(tmp_path)
    err = _setup(project, "build_ext", "--inplace")
    assert "motionvm: the motion cycle is compiled already from these sources; reused" in err
    assert "compiling" not in err
    # a build tree (pip install .) gets copies of the extensions and the record
    _setup(project, "build_ext", "--build-lib", "out")
    for m in cb.MODULES:
        assert (project / "out" / (m.replace(".", "/") + SUFFIX)).exists()
    assert cb.reusable(project / "out" / "motionvm", BUILD, SUFFIX) is False  # no sources
    assert json.loads((project / "out/motionvm" / cb.RECORD).read_text())[cb.BUILD_KEY] == BUILD
    # an edited source is compiled again, and the message comes first
    src = project / "src/motionvm/motion/profile.py"
    src.write_text("# edited\n", encoding="utf-8")
    err = _setup(project, "build_ext", "--inplace")
    assert "motionvm: compiling the motion cycle (6 modules" in err
    assert err.index("compiling the motion cycle") < err.index("compiled build skipped")


def _python(code: str, pure: bool) -> str:
    env = dict(os.environ)
    env.pop("MOTIONVM_PURE", None)
    if pure:
        env["MOTIONVM_PURE"] = "1"
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=120, check=True)  # fmt: skip
    return r.stdout


def test_motionvm_pure_loads_every_module_from_its_source():
    code = (
        "import importlib, motionvm\n"
        "from motionvm import compiled_build as cb\n"
        "print(cb.STATUS)\n"
        "for m in cb.MODULES: print(importlib.import_module(m).__file__)\n"
    )
    status, *files = _python(code, pure=True).splitlines()
    assert status.startswith("pure Python")
    assert files and all(f.endswith(".py") for f in files)


PROGRAM = """
void main() {
    int k;
    for (k = 0; k < 3; k++) Enable(k);
    for (k = 0; k < 3; k++) Till(IsEnabled(k));
    SetSMTime(2, 20);
    for (k = 0; k < 6; k++) {
        MoveAbs(0, k % 2 ? -12.5 : 73.25);
        MoveRel(1, 17.125);
        MoveAbs(2, k * 9.5);
        Till(IsInPos(0) && IsInPos(1));
        Print("%d %.12f %.12f %.12f", system_timeInMs, GetPosFb(0), GetPosFb(1), GetRefPos(2));
        Sleep(k * 3);
    }
    MoveVel(1, 40.0);
    Till(GetPosFb(1) > 130.0);
    Stop(1);
    for (k = 0; k < 3; k++) Till(IsInPos(k));
    Print("%d %.12f %.12f %.12f", system_timeInMs, GetPosFb(0), GetPosFb(1), GetPosFb(2));
}
"""


@pytest.mark.skipif(cb.STATUS != "compiled", reason="no compiled build in use")
def test_compiled_and_pure_runs_are_identical(tmp_path):
    """Stdout, --stamp times and the scope file, skipping and stepping, both builds."""
    src = tmp_path / "moves.hmpl"
    src.write_text(PROGRAM, encoding="utf-8")
    outputs = set()
    for pure in (False, True):
        for skip in (True, False):
            scope = tmp_path / f"scope-{pure}-{skip}.csv"
            argv = ["run", "--stamp", "--no-progress", "--scope", "axis0.pos_fb,axis1.ref_pos,axis2.ref_vel,axis2.vel_fb,axis1.coe_pos_fb",
                    "--scope-out", str(scope), str(src)] + ([] if skip else ["--no-skip"])  # fmt: skip
            code = f"import sys; from motionvm.cli import main; sys.exit(main({argv!r}))"
            out = _python(code, pure)
            outputs.add((out, scope.read_bytes()))
    assert len(outputs) == 1
    out = outputs.pop()[0]
    assert out.count("\n") == 7
