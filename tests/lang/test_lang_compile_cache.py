"""The compile cache of PDL programs and GDL applications: an unchanged program compiles
nothing and runs the same, a changed file or `#include` compiles again, a damaged entry
is compiled again and written anew, an unwritable cache folder still runs, warnings are
reported on every use, and a compile with coverage probes stands aside."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from motionvm.api import Simulation
from motionvm.lang.coverage import Coverage, collecting
from motionvm.lang.gdl import compiler as gdl_compiler
from motionvm.lang.gdl.language import LANGUAGE as GDL
from motionvm.lang.interface import CompileRequest, LineTable, Source
from motionvm.lang.pdl import program as pdl_program
from motionvm.lang.pdl.language import LANGUAGE as PDL
from motionvm.sim.machine import DEFAULT_MACHINE

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

PDL_MAIN = """#include "defs.h"
#long a_very_long_name1;
#task/0;
a_very_long_name1 = STEP * 2;
printl("value %ld", a_very_long_name1);
halt;
"""

GDL_WARNED = """MODULE m;
  DIGITAL$FLAG flip [ ];
  PROCEDURE loop;
  DECLARE { STATUS OF flip };
  BEGIN
    STATUS OF flip = NOT STATUS OF flip;
  END$PROCEDURE;
END$MODULE;
"""


@pytest.fixture
def compiles(monkeypatch) -> list[str]:
    """The PDL files and GDL applications (their first file) compiled, in order; a
    compile read from the cache adds nothing."""
    seen: list[str] = []
    real_pdl, real_gdl = pdl_program._compile_pdl, gdl_compiler._compile_app

    def pdl(path, *args):
        seen.append(path)
        return real_pdl(path, *args)

    def gdl(paths, *args):
        seen.append(paths[0])
        return real_gdl(paths, *args)

    monkeypatch.setattr(pdl_program, "_compile_pdl", pdl)
    monkeypatch.setattr(gdl_compiler, "_compile_app", gdl)
    return seen


@pytest.fixture
def pdl_file(tmp_path) -> Path:
    (tmp_path / "defs.h").write_text("#define STEP 3\n")
    path = tmp_path / "main.pdl"
    path.write_text(PDL_MAIN)
    return path


@pytest.fixture
def gdl_file(tmp_path) -> Path:
    path = tmp_path / "packer.gdl"
    shutil.copy(EXAMPLES / "02_gdl_packer.gdl", path)
    return path


def run(path: Path, until: float = 0.5) -> tuple[list[str], list[str]]:
    """(messages, rendered diagnostics) of a short run of one program file (a GDL
    application with the example's scenario)."""
    kw = {"scenario": EXAMPLES / "02_gdl_packer.toml"} if path.suffix == ".gdl" else {}
    with Simulation.from_files([path], **kw) as sim:
        sim.run(until=until)
        return list(sim.messages), list(sim.diagnostics)


def compile_(language, *sources: Source):
    result = language.compile(sources, CompileRequest(DEFAULT_MACHINE, alone=True))
    assert result.program is not None, [d.headline() for d in result.diagnostics]
    return result


@pytest.mark.parametrize("kind", ["pdl", "gdl"])
def test_an_unchanged_program_is_read_back_and_runs_the_same(
    kind, pdl_file, gdl_file, compile_cache, compiles
):
    path = pdl_file if kind == "pdl" else gdl_file
    first = run(path, 2.0)
    assert compiles == [str(path)]
    assert list(compile_cache.glob(f"{kind}-*.mvc"))
    assert run(path, 2.0) == first  # messages and warnings
    assert compiles == [str(path)]  # nothing compiled the second time
    assert first[0]
    if kind == "pdl":
        assert first[0] == ["value 6"] and "17 characters" in first[1][0]


def test_a_changed_include_or_file_compiles_again(pdl_file, compile_cache, compiles):
    assert run(pdl_file)[0] == ["value 6"]
    (pdl_file.parent / "defs.h").write_text("#define STEP 5\n")
    assert run(pdl_file)[0] == ["value 10"]
    assert run(pdl_file)[0] == ["value 10"]
    assert len(compiles) == 2  # the changed program is cached in turn
    pdl_file.write_text(PDL_MAIN.replace("STEP * 2", "STEP * 3"))
    assert run(pdl_file)[0] == ["value 15"]
    assert len(compiles) == 3


def test_a_changed_gdl_file_compiles_again(tmp_path, compile_cache, compiles):
    path = tmp_path / "app.gdl"
    path.write_text(GDL_WARNED)
    compile_(GDL, Source(str(path)))
    compile_(GDL, Source(str(path)))
    assert len(compiles) == 1
    path.write_text(GDL_WARNED.replace("PROCEDURE loop", "PROCEDURE other"))
    result = compile_(GDL, Source(str(path)))
    assert len(compiles) == 2
    assert list(result.program.functions) == ["other"]


@pytest.mark.parametrize("kind", ["pdl", "gdl"])
@pytest.mark.parametrize("damage", [b"", b"MVMC\x01garbage", b"not an entry at all"])
def test_a_damaged_entry_is_compiled_again_and_rewritten(
    kind, damage, pdl_file, gdl_file, compile_cache, compiles
):
    path = pdl_file if kind == "pdl" else gdl_file
    first = run(path)
    (entry,) = compile_cache.glob(f"{kind}-*.mvc")
    size = entry.stat().st_size
    entry.write_bytes(damage if damage else entry.read_bytes()[: size // 2])
    assert run(path) == first
    assert len(compiles) == 2
    assert entry.stat().st_size > size * 0.9  # written again, whole
    run(path)
    assert len(compiles) == 2


@pytest.mark.parametrize("kind", ["pdl", "gdl"])
def test_an_unwritable_cache_folder_still_runs(
    kind, pdl_file, gdl_file, tmp_path, monkeypatch, compiles
):
    path = pdl_file if kind == "pdl" else gdl_file
    blocked = tmp_path / "not-a-folder"
    blocked.write_text("a file where the cache folder should be\n")
    monkeypatch.delenv("MOTIONVM_NO_CACHE", raising=False)
    monkeypatch.setenv("MOTIONVM_CACHE_DIR", str(blocked / "cache"))
    first = run(path)
    assert run(path) == first and first[0]
    assert len(compiles) == 2  # nothing could be kept: each run compiles


@pytest.mark.parametrize("language", [PDL, GDL], ids=["pdl", "gdl"])
def test_warnings_and_text_sources_are_cached(language, compile_cache, compiles):
    name, text = (
        ("inline.pdl", PDL_MAIN.replace('#include "defs.h"\n', "#define STEP 3\n"))
        if language is PDL
        else ("inline.gdl", GDL_WARNED)
    )
    cold = compile_(language, Source(name, text)).diagnostics
    warm = compile_(language, Source(name, text)).diagnostics
    assert len(compiles) == 1
    assert [d.severity for d in cold] == ["warning"] and warm == cold
    compile_(language, Source(name, text + "\n"))
    assert len(compiles) == 2


@pytest.mark.parametrize("kind", ["pdl", "gdl"])
def test_the_generated_python_of_a_cached_program_is_complete(
    kind, pdl_file, gdl_file, compile_cache
):
    language, path = (PDL, pdl_file) if kind == "pdl" else (GDL, gdl_file)
    cold = compile_(language, Source(str(path)))
    warm = compile_(language, Source(str(path)))
    assert language.python_source(warm.program) == language.python_source(cold.program)
    assert "def " in language.python_source(warm.program)


@pytest.mark.parametrize("kind", ["pdl", "gdl"])
def test_checks_and_coverage_compiles_stand_aside(
    kind, pdl_file, gdl_file, compile_cache, compiles
):
    language, path = (PDL, pdl_file) if kind == "pdl" else (GDL, gdl_file)
    language.check([Source(str(path))])
    with collecting(Coverage(lambda p: LineTable(p, frozenset()))):
        compile_(language, Source(str(path)))
        compile_(language, Source(str(path)))
    assert not compile_cache.exists() or not list(compile_cache.glob("*.mvc"))
    assert len(compiles) == 3


def test_a_deeply_nested_application_is_cached_and_read_back(tmp_path, compile_cache, compiles):
    """Its entry holds syntax trees 3,000 levels deep: stored and read with room to
    recurse, as the compile runs."""
    terms = " + ".join(["VALUE OF a"] * 3_000)
    path = tmp_path / "deep.gdl"
    path.write_text(
        "MODULE m;\n  INTEGER$VARIABLE s [ ];\n  INTEGER$VARIABLE a [ INITIAL$VALUE = 1 ];\n"
        "  DIGITAL$FLAG go [ ];\n  PROCEDURE p;\n  DECLARE { STATUS OF go };\n  BEGIN\n"
        f"    VALUE OF s = {terms};\n  END$PROCEDURE;\nEND$MODULE;\n"
    )
    cold = compile_(GDL, Source(str(path)))
    assert list(compile_cache.glob("gdl-*.mvc"))
    warm = compile_(GDL, Source(str(path)))
    assert len(compiles) == 1
    assert list(warm.program.functions) == list(cold.program.functions) == ["p"]


def test_a_value_that_cannot_be_pickled_is_not_cached(tmp_path):
    from motionvm.source.cache import CompileCache

    cache = CompileCache(tmp_path / "c", "x")
    cache.store("k", {"f": lambda: 1})  # (a lambda is no data)
    assert cache.load("k") is None
