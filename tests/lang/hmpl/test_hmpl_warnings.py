"""Compiler warnings of HMPL: built-ins that are not implemented, -Wformat, -Wparentheses,
unused variables, unreachable code; and no cascade of errors after a failed declaration."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from motionvm.lang.hmpl.catalog import MACRO_NAMES, builtin_signatures
from motionvm.lang.hmpl.compiler import TaskFile, compile_tasks
from motionvm.lang.hmpl.lib import implemented_builtins
from motionvm.source.diagnostics import DiagnosticSink

REPO = Path(__file__).resolve().parents[3]


def diagnostics(src: str) -> list[str]:
    """'LINE:COL: severity: message' of every diagnostic of a one-task program."""
    sink = DiagnosticSink()
    compile_tasks([TaskFile(0, "w.hmpl", src)], sink)
    return [f"{d.pos.line}:{d.pos.col}: {d.severity}: {d.message}" for d in sink.items]


def warnings(body: str, decls: str = "") -> list[str]:
    """The warnings of `body` as main's body (line 2 on), with no errors allowed."""
    got = diagnostics(f"{decls}void main() {{\n{body}\n}}\n" if not decls else decls + body)
    assert not [d for d in got if ": error: " in d], got
    return [d.split(": warning: ", 1)[1] for d in got if ": warning: " in d]


# ---------------------------------------------------------------- not implemented


def test_every_built_in_of_the_manual_is_implemented():
    missing = [
        name
        for name in builtin_signatures()
        if name not in implemented_builtins() and name not in MACRO_NAMES
    ]
    assert missing == []


def without(name: str):
    """The implemented built-ins as if `name` had no implementation (a library that
    failed to provide it): the compiler's fallback for such a call."""
    impl = dict(implemented_builtins())
    del impl[name]
    return lambda: impl


def test_a_call_of_a_built_in_that_is_not_implemented_warns_with_its_section(monkeypatch):
    monkeypatch.setattr("motionvm.lang.hmpl.compiler.implemented_builtins", without("GetGrpCmdNum"))
    got = diagnostics('void main() {\n    int v = GetGrpCmdNum(3);\n    Print("%d", v);\n}\n')
    assert got == [
        "2:13: warning: GetGrpCmdNum (manual 8.3.27) is not implemented; the task will stop here"
    ]


def test_implemented_built_ins_and_special_names_give_no_warning():
    body = (
        "    int v = HIMC_GPI(1);\n"
        "    Till(v == 0);\n"
        '    Print("%d %d", _TASKID_, v);\n'
        "    Sleep(1);\n"
    )
    assert warnings(body) == []


# ---------------------------------------------------------------- -Wformat


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            'Print("%d", 1.5);',
            "format '%d' expects an argument of type 'int', but argument 2 has type 'double'",
        ),
        (
            'Print("x=%f", 2);',
            "format '%f' expects an argument of type 'double', but argument 2 has type 'int'",
        ),
        (
            'Print("%s", 3);',
            "format '%s' expects an argument of type 'char *', but argument 2 has type 'int'",
        ),
        (
            'StringPrint(buf, "%d", 1.5);',
            "format '%d' expects an argument of type 'int', but argument 3 has type 'double'",
        ),
        (
            'SendMsgEvent("%5.2f %s", 1.0, 2.0);',
            "format '%s' expects an argument of type 'char *', but argument 3 has type 'double'",
        ),
        ('Print("%d %d", 1);', "format '%d' expects a matching 'int' argument"),
        ('Print("%d", 1, 2);', "too many arguments for format"),
        ('Print("plain", 1);', "too many arguments for format"),
        (
            'Print("%*d", 2.0, 1);',
            "field width specifier '*' expects an argument of type 'int', but argument 2 "
            "has type 'double'",
        ),
        (
            'Print("%lld", 1);',
            "format '%lld' expects an argument of type 'long long int', but argument 2 "
            "has type 'int'",
        ),
        (
            'Print("%d", big);',
            "format '%d' expects an argument of type 'int', but argument 2 has type 'int64_t'",
        ),
        (
            'Print("%p", 1);',
            "format '%p' expects an argument of type 'void *', but argument 2 has type 'int'",
        ),
    ],
)
def test_format_arguments_that_do_not_fit_warn(call, message):
    body = f'    char buf[64];\n    int64_t big = 1;\n    {call}\n    Print("%s%d", buf, (int)big);'
    assert warnings(body) == [message]


def test_format_arguments_that_fit_give_no_warning():
    body = (
        "    char buf[64];\n"
        "    char c = 'a';\n"
        "    int16_t s = 2;\n"
        "    float f = 1.5f;\n"
        "    uint32_t u = 7;\n"
        "    int64_t big = 9;\n"
        '    Print("%d %i %u %x %c %s %f %e %g %p %% %5.2f %-3d", 1, c, u, s, c, buf, f, 2.0, '
        "3.0, &c, 1.0, 4);\n"
        '    Print("%lld %*.*f %.*s", big, 8, 2, 1.0, 3, "abcdef");\n'
        '    StringPrint(buf, "%s=%d", "n", 3);\n'
        '    SendMsgEvent("%d", u);'
    )
    assert warnings(body) == []


def test_a_format_that_is_not_a_literal_is_not_checked():
    assert warnings('    char fmt[8] = "%d %d";\n    Print(fmt, 1.5);') == []


def test_the_format_warning_points_at_the_argument_or_the_format():
    got = diagnostics('void main() {\n    Print("%d %d", 1.5);\n}\n')
    assert got[0].startswith("2:20: warning: format '%d' expects an argument of type 'int'")
    assert got[1].startswith("2:11: warning: format '%d' expects a matching 'int' argument")


# ---------------------------------------------------------------- -Wparentheses

PARENS = "suggest parentheses around assignment used as truth value"


@pytest.mark.parametrize(
    "stmt",
    [
        'if (n = 4) Print("x");',
        "while (n = 0) { }",
        "do { } while (n = 0);",
        "for (; n = 0; ) { }",
        "Till(n = 0);",
        "Till(n = 0) { Sleep(1); }",
    ],
)
def test_an_assignment_used_as_a_condition_warns(stmt):
    assert warnings(f"    int n = 1;\n    {stmt}") == [PARENS]


@pytest.mark.parametrize(
    "stmt",
    [
        'if ((n = 4)) Print("x");',
        "while ((n = 0)) { }",
        'if (n == 4) Print("x");',
        "n = 4;",
        'if (n += 1) Print("x");',
        'int m = (n = 2) ? 1 : 0; Print("%d", m);',
        "Till((n = 0));",
        'if (!(n = 0)) Print("x");',
    ],
)
def test_extra_parentheses_or_a_comparison_give_no_warning(stmt):
    assert warnings(f"    int n = 1;\n    {stmt}") == []


def test_the_parentheses_warning_points_at_the_assignment():
    got = diagnostics("void main() {\n    int n;\n    if (n = 4) n = 5;\n}\n")
    assert got == [f"3:11: warning: {PARENS}"]


# ---------------------------------------------------------------- unused variables


def test_an_unused_local_warns_at_its_declaration():
    got = diagnostics("void main() {\n    int used = 1;\n    double idle;\n    used++;\n}\n")
    assert got == ["3:12: warning: unused variable 'idle'"]


@pytest.mark.parametrize(
    "body",
    [
        "    int x;\n    x = 3;",  # assigned only: gcc's -Wunused-variable is quiet too
        '    int x = 1;\n    Print("%d", x);',
        "    int x;\n    int n = sizeof(x);\n    n++;",
        "    int x;\n    int *p = &x;\n    *p = 1;",
        "    int a[4];\n    a[1] = 2;",
        "    int x = 0;\n    { x++; }",
    ],
)
def test_a_used_local_gives_no_warning(body):
    assert warnings(body) == []


def test_parameters_and_globals_are_not_reported():
    src = "int g;\nint f(int unused_param) { return 1; }\nvoid main() { f(2); }\n"
    assert warnings("", decls=src) == []


def test_unused_locals_of_inner_blocks_and_for_loops_warn():
    body = (
        "    int x = 1;\n"
        "    { int x = 2; }\n"
        '    for (int i = 0, j = 0; i < 2; i++) { Print("%d", x); }'
    )
    assert warnings(body) == ["unused variable 'x'", "unused variable 'j'"]


# ---------------------------------------------------------------- unreachable code


@pytest.mark.parametrize(
    "body",
    [
        '    return;\n    Print("dead");',
        '    while (1) { break; Print("dead"); }',
        '    for (int i = 0; i < 3; i++) { continue; Print("dead"); }',
        '    goto end;\n    Print("dead");\nend:\n    Print("live");',
    ],
)
def test_a_statement_after_a_jump_is_unreachable(body):
    assert warnings(body) == ["unreachable code"]


def test_one_warning_per_stretch_of_dead_code():
    got = diagnostics('void main() {\n    return;\n    Print("a");\n    Print("b");\n}\n')
    assert got == ["3:5: warning: unreachable code"]


@pytest.mark.parametrize(
    "body",
    [
        '    goto end;\nend:\n    Print("live");',
        "    int n = 1;\n    switch (n) {\n    case 1: n = 2; break;\n    case 2: n = 3; break;"
        "\n    default: break;\n    }",
        "    int n = 1;\n    switch (n) {\n    case 1: return;\n        break;\n    }",
        "    if (1) return;\n    Sleep(1);",
        "    return;\n    ;",
    ],
)
def test_labels_cases_and_conditional_jumps_keep_code_reachable(body):
    assert warnings(body) == []


# ---------------------------------------------------------------- no cascades


@pytest.mark.parametrize(
    ("decl", "error"),
    [
        ("    int a[0];", "3:11: error: size of array 'a' must be positive (it is 0)"),
        ("    int a = nothing;", "3:13: error: 'nothing' undeclared"),
        ("    int a = 1, a = 2;", "3:16: error: redefinition of 'a'"),
        ("    void a;", "3:10: error: variable 'a' declared void"),
    ],
)
def test_a_failed_local_declaration_still_declares_its_name(decl, error):
    src = f"void main() {{\n    int other = 1;\n{decl}\n    a = 3;\n    other = a + 1;\n}}\n"
    assert diagnostics(src) == [error]


def test_a_failed_global_declaration_still_declares_its_name():
    src = 'int table[-2];\nvoid main() {\n    table[0] = 1;\n    Print("%d", table[0]);\n}\n'
    assert diagnostics(src) == ["1:11: error: size of array 'table' must be positive (it is -2)"]


def test_a_failed_function_declaration_still_declares_its_name():
    src = "int f(int v[0]) { return 1; }\nvoid main() {\n    int r = f(0);\n    r++;\n}\n"
    got = diagnostics(src)
    assert len(got) == 1 and "must be positive" in got[0], got


def test_a_failed_struct_or_typedef_still_names_its_type():
    src = (
        "typedef int row_t[0];\n"
        "struct S { int a[-1]; };\n"
        "row_t g;\n"
        "void main() {\n"
        "    row_t r;\n"
        "    struct S s;\n"
        "    r[0] = 1;\n"
        "    s.a[0] = g[0];\n"
        "}\n"
    )
    assert diagnostics(src) == [
        "1:19: error: size of array 'row_t' must be positive (it is 0)",
        "2:18: error: size of array 'a' must be positive (it is -1)",
    ]


# ---------------------------------------------------------------- the programs of the repo


_TASK = re.compile(r"//\s*task\s+(\d+):\s*(\S+)")


def _programs() -> list[Path]:
    """The golden programs that should compile (no `// error:` directive), and examples."""
    golden = sorted((REPO / "tests" / "programs" / "hmpl").rglob("*.hmpl"))
    ok = [p for p in golden if "." not in p.stem and "// error:" not in p.read_text("utf-8")]
    return ok + sorted((REPO / "examples").glob("*.hmpl"))


@pytest.mark.parametrize("path", _programs(), ids=lambda p: str(p.relative_to(REPO)))
def test_every_program_of_the_repo_still_compiles(path):
    tasks = [TaskFile(0, str(path))] + [
        TaskFile(int(m.group(1)), str(path.parent / m.group(2)))
        for m in _TASK.finditer(path.read_text("utf-8"))
    ]
    sink = DiagnosticSink()
    prog, _mem = compile_tasks(tasks, sink)
    assert prog is not None, [d.headline() for d in sink.items]
