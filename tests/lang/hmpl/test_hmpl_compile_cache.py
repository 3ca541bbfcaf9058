"""The compile cache of HMPL programs: an unchanged program compiles nothing, any change
of an input (the file, a header it includes, its task id, the compiler) compiles again,
a damaged entry is compiled again, and warnings are reported on every use."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.api import Simulation
from motionvm.lang.hmpl import compiler, program_cache
from motionvm.lang.hmpl.language import LANGUAGE
from motionvm.lang.interface import CompileRequest, Source
from motionvm.sim.machine import DEFAULT_MACHINE
from motionvm.source.diagnostics import render_diagnostic

PROGRAM = """#include "limits.h"
int table[4] = {1, 2, 3, 4};
char *name = "cached";
void main() {
    int unused;
    system_ltest0 = table[3] * LIMIT + _TASKID_;
    Print("%s %d", name, system_ltest0);
}
"""


@pytest.fixture
def parses(monkeypatch) -> list[str]:
    """The paths the compiler parses, in order (a cache hit parses nothing)."""
    seen: list[str] = []
    real = compiler.parse_file

    def counting(path, **kw):
        seen.append(path)
        return real(path, **kw)

    monkeypatch.setattr(compiler, "parse_file", counting)
    return seen


@pytest.fixture
def program(tmp_path) -> Path:
    (tmp_path / "limits.h").write_text("#define LIMIT 10\n")
    path = tmp_path / "main.hmpl"
    path.write_text(PROGRAM)
    return path


def compile_(*sources: Source):
    result = LANGUAGE.compile(sources, CompileRequest(DEFAULT_MACHINE))
    assert result.program is not None, [d.headline() for d in result.diagnostics]
    return result


def run(path: Path, task: int = 0) -> tuple[list[str], list[str], int]:
    """(messages, rendered warnings, system_ltest0) of running the program briefly."""
    with Simulation([Source(str(path), task=task)]) as sim:
        sim.run(until=0.01)
        return list(sim.messages), list(sim.diagnostics), sim.read("system_ltest0")


def test_an_unchanged_program_is_read_back_and_runs_the_same(program, compile_cache, parses):
    first = run(program)
    assert parses == [str(program)]
    assert list(compile_cache.glob("hmpl-*.mvc"))
    assert run(program) == first  # messages, warnings, result
    assert parses == [str(program)]  # nothing parsed the second time
    assert first[0] == ["cached 40"]


def test_warnings_are_reported_alike_from_the_cache(program, compile_cache, parses):
    cold = compile_(Source(str(program))).diagnostics
    warm = compile_(Source(str(program))).diagnostics
    assert len(parses) == 1
    assert [d.severity for d in cold] == ["warning"] and "unused" in cold[0].message
    assert warm == cold
    assert [render_diagnostic(d) for d in warm] == [render_diagnostic(d) for d in cold]


@pytest.mark.parametrize(
    "change",
    ["main file", "header", "task id", "compiler"],
)
def test_any_changed_input_compiles_again(program, compile_cache, parses, monkeypatch, change):
    run(program)
    task = 0
    if change == "main file":
        program.write_text(PROGRAM.replace("LIMIT +", "LIMIT * 2 +"))
        expected = 80
    elif change == "header":
        (program.parent / "limits.h").write_text("#define LIMIT 100\n")
        expected = 400
    elif change == "task id":  # task 3's main does not start by itself: its code names it
        task, expected = 3, 0
    else:
        real = program_cache.package_digest
        monkeypatch.setattr(program_cache, "package_digest", lambda *a: real(*a) + "-next")
        expected = 40
    assert run(program, task)[2] == expected
    assert len(parses) == 2
    run(program, task)
    assert len(parses) == 2  # the changed program is cached in turn
    assert list(compile_(Source(str(program), task=task)).program[0].tasks) == [task]


def test_the_compiler_digest_covers_every_file_of_the_compiler(tmp_path, monkeypatch):
    from motionvm.source import cache

    (tmp_path / "lang").mkdir()
    (tmp_path / "lang" / "lower.py").write_text("X = 1\n")
    (tmp_path / "__init__.py").write_text('__version__ = "1.0"\n')
    monkeypatch.setattr(cache, "_PACKAGE", tmp_path)
    cache.package_digest.cache_clear()
    try:
        before = cache.package_digest(("lang",))
        (tmp_path / "lang" / "lower.py").write_text("X = 2\n")
        cache.package_digest.cache_clear()
        after_code = cache.package_digest(("lang",))
        (tmp_path / "__init__.py").write_text('__version__ = "1.1"\n')
        cache.package_digest.cache_clear()
        after_version = cache.package_digest(("lang",))
    finally:
        cache.package_digest.cache_clear()
    assert len({before, after_code, after_version}) == 3


@pytest.mark.parametrize("damage", [b"", b"MVMC\x01garbage", b"not an entry at all"])
def test_a_damaged_entry_is_compiled_again(program, compile_cache, parses, damage):
    first = run(program)
    (entry,) = compile_cache.glob("hmpl-*.mvc")
    entry.write_bytes(damage if damage else entry.read_bytes()[:100])
    assert run(program) == first
    assert len(parses) == 2
    assert entry.stat().st_size > 1000  # written again, whole


def test_a_text_program_is_cached_by_its_text(compile_cache, parses):
    a = compile_(Source("inline.hmpl", "void main() { system_ltest0 = 1; }\n", 0))
    compile_(Source("inline.hmpl", "void main() { system_ltest0 = 1; }\n", 0))
    assert len(parses) == 1
    compile_(Source("inline.hmpl", "void main() { system_ltest0 = 2; }\n", 0))
    assert len(parses) == 2
    assert a.program is not None


def test_the_generated_python_of_a_cached_program_is_complete(program, compile_cache):
    cold = compile_(Source(str(program)))
    warm = compile_(Source(str(program)))
    assert LANGUAGE.python_source(warm.program) == LANGUAGE.python_source(cold.program)
    assert "def g_main" in LANGUAGE.python_source(warm.program)


def test_nothing_is_cached_when_turned_off_or_only_checked(program, tmp_path, monkeypatch, parses):
    folder = tmp_path / "off"
    monkeypatch.setenv("MOTIONVM_CACHE_DIR", str(folder))
    monkeypatch.setenv("MOTIONVM_NO_CACHE", "1")
    compile_(Source(str(program)))
    compile_(Source(str(program)))
    monkeypatch.delenv("MOTIONVM_NO_CACHE")
    LANGUAGE.check([Source(str(program))])
    assert not folder.exists()
    assert len(parses) == 3


def test_a_program_with_errors_is_not_cached(tmp_path, compile_cache):
    bad = tmp_path / "bad.hmpl"
    bad.write_text("void main() { undeclared = 1; }\n")
    for _ in range(2):
        result = LANGUAGE.compile([Source(str(bad))], CompileRequest(DEFAULT_MACHINE))
        assert result.program is None and result.diagnostics
    assert not list(compile_cache.glob("*.mvc"))
