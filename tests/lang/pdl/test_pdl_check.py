"""PDL checker: rendered diagnostics, limits, symbols, names, code units, the catalog.

The programs under tests/programs/pdl/ carry their expected diagnostics (`// error:`,
`// warning:`, `// diagnostics: exact`) or `// check:` (they must compile clean); the
runner of all golden programs, tests/programs/test_programs.py, checks them.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.pdl import compile_front, front_end
from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl.symbols import code_units
from motionvm.source import DiagnosticSink, render_diagnostic

PROGRAMS = Path(__file__).parents[2] / "programs" / "pdl"
CLEAN = sorted((PROGRAMS / "manual").rglob("*.pdl")) + sorted((PROGRAMS / "valid").glob("*.pdl"))


def test_clean_programs_are_programs() -> None:
    """The programs that must compile clean (checked by the golden runner) have code."""
    for path in CLEAN:
        program = compile_front(str(path), sink=DiagnosticSink())
        assert program is not None and program.items, path.name


def check_text(text: str) -> tuple[object, list[str]]:
    sink = DiagnosticSink()
    result = front_end("mem/c.pdl", sink=sink, text=text)
    return result, [f"{d.pos.line}:{d.pos.col}: {d.message}" for d in sink.errors()]


def test_rendered_diagnostic_has_file_line_col_source_and_caret() -> None:
    sink = DiagnosticSink()
    compile_front("mem/r.pdl", sink=sink, text="#long a;\n  a = b;\n")
    assert render_diagnostic(sink.items[0]) == (
        "mem/r.pdl:2:7: error: undeclared variable 'b'\n  a = b;\n      ^"
    )


def test_program_memory_limit_of_128_kb() -> None:
    ok, errors = check_text("#long a;\n" + "a = 1;\n" * 32_000)
    assert ok is not None and errors == []
    _, errors = check_text("#long a;\n" + "a = 1;\n" * 33_000)
    assert errors == [
        (
            "32770:1: the program needs more than 131,072 bytes (128 KB) of drive "
            "program memory from here on"
        )
    ]


def test_user_memory_of_exactly_16000_words_is_allowed() -> None:
    result, errors = check_text("#long a[15999];\n#short b, c;\n")
    assert errors == [] and result is not None
    assert result.symbols.user_bytes == 64_000  # type: ignore[attr-defined]


def test_symbols_of_a_program() -> None:
    result, errors = check_text(
        "#short Eli, Rafi, Benny, My_array[100], N;\n"
        "#long v, *pv;\n"
        "proc add3(long a, long b, long c, long *sum) do #long tmp; tmp = a + b; end;\n"
        "#task/1;\n"
        "_host: add3(1, 2, 3, &v);\n"
        "ret;\n"
    )
    assert errors == []
    syms = result.symbols  # type: ignore[attr-defined]
    assert [(s.name, s.type, s.size, s.offset) for s in syms.globals.values()] == [
        ("Eli", "short", 1, 0),
        ("Rafi", "short", 1, 2),
        ("Benny", "short", 1, 4),
        ("My_array", "short", 100, 6),
        ("N", "short", 1, 206),
        ("v", "long", 1, 208),
        ("pv", "long", 1, 212),
    ]
    assert syms.globals["pv"].pointer
    assert set(syms.tasks) == {1} and set(syms.labels) == {"_host"}
    proc = syms.procs["add3"]
    assert [(s.name, s.scope, s.offset) for s in proc.locals.values()] == [
        ("a", "param", 0),
        ("b", "param", 1),
        ("c", "param", 2),
        ("sum", "param", 3),
        ("tmp", "local", 4),
    ]
    call = result.program.items[5]  # type: ignore[attr-defined]
    assert isinstance(call, n.ProcCall) and syms.symbol_of(call) is proc


def test_system_names_resolve_ignoring_case() -> None:
    result, errors = check_text("x_jvl = 2000; X_STOP_M = 1; till (~X_RUN);")
    assert errors == []
    syms = result.symbols  # type: ignore[attr-defined]
    first = result.program.items[0]  # type: ignore[attr-defined]
    assert syms.symbol_of(first.target).name == "X_jvl"


def test_locals_hide_globals_and_labels_are_per_procedure() -> None:
    result, errors = check_text(
        "#float x;\nproc p(long x) do loop1: x = x + 1; goto loop1; end;\n"
        "proc q() do loop1: goto loop1; end;\nloop1: goto loop1;\n"
    )
    assert errors == [] and result is not None


def test_forward_labels_and_prototypes() -> None:
    _, errors = check_text("call later;\nf(1);\nproc f(long a) do end;\nlater: ret;\n")
    assert errors == [
        (
            "2:1: procedure 'f' is not declared before this call; define it above "
            "or add a prototype 'proc f(...);'"
        )
    ]
    _, errors = check_text(
        "proc f(long a);\ncall later;\nf(1);\nproc f(long a) do end;\nlater: ret;\n"
    )
    assert errors == []


def test_variables_must_be_declared_before_use() -> None:
    _, errors = check_text("x = 1;\n#long x;\n")
    assert errors == ["1:1: undeclared variable 'x'"]


@pytest.mark.parametrize(
    ("stmt", "units"),
    [
        ("goto a;", 1),
        ("exitproc;", 1),
        ('printl/103("x");', 2),
        ('printl/103("%d %d ", a, a);', 4),
        ("if (a>1) do a=1; else do a=2; end;", 4),
        ("loop(2) do a=1; end;", 3),
        ("a:", 0),
    ],
)
def test_code_units(stmt: str, units: int) -> None:
    sink = DiagnosticSink()
    from motionvm.lang.pdl.parser import parse
    from motionvm.lang.pdl.preprocess import preprocess

    program, _ = parse(preprocess("mem/u.pdl", sink, stmt), sink)
    assert code_units(program.items[0]) == units


def test_indirect_goto_table_of_the_manual_lands_on_each_message() -> None:
    text = (PROGRAMS / "manual" / "s2_4_2_1_print_msg.pdl").read_text()
    for row in range(5):
        body = text.replace("goto prlabel[flag];", f"goto prlabel[{row * 5}];")
        _, errors = check_text(body)
        assert errors == []
    _, errors = check_text(text.replace("goto prlabel[flag];", "goto prlabel[3];"))
    assert errors == [
        (
            "9:14: 'goto prlabel[3]' lands inside the statement at line 12 "
            "(4 code units starting at prlabel[0])"
        )
    ]


def test_unreadable_file_is_a_diagnostic_not_a_traceback(tmp_path: Path) -> None:
    sink = DiagnosticSink()
    missing = str(tmp_path / "missing.pdl")
    assert compile_front(missing, sink=sink) is None
    assert [d.headline() for d in sink.items] == [
        f"{missing}:1:1: error: cannot read '{missing}': No such file or directory"
    ]


def test_system_catalog() -> None:
    from motionvm.lang.pdl import sysvars

    issue_names = [
        "X_vel_max",
        "X_acc",
        "X_dcc",
        "X_new_sm_fac",
        "X_trg",
        "X_jvl",
        "X_stop_m",
        "x_run",
        "x_ref_pos",
        "x_home",
        "X_LL",
        "LEFT_LIM",
        "fclk",
        "lcdout",
        "task_num",
        "task_prior",
        "ltest1",
        "ff1",
        "IN1",
    ]
    assert all(sysvars.lookup(name) is not None for name in issue_names)
    states = [v for v in sysvars.SYSVARS.values() if v.kind == "state"]
    assert len({s.address for s in states}) == len(states)
    assert sysvars.lookup("fclk").read_only and not sysvars.lookup("X_trg").read_only
    assert sysvars.lookup("task_prior").size == 4
    assert sysvars.is_state("x_run") and not sysvars.is_state("X_trg")
    assert sysvars.lookup("x_jvl") is sysvars.lookup("X_jvl")
