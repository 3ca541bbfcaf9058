"""The language interface: the registry, and what each language shows tools (line tables,
symbols, documentation), compiles and dumps through it."""

from __future__ import annotations

import pytest

from motionvm.lang import (
    LANGUAGES,
    CompileRequest,
    LanguageInputError,
    Source,
    language_named,
    language_of,
    suffixes,
)
from motionvm.sim.machine import DEFAULT_MACHINE

HMPL = """\
int count = 0;
struct pt { int x; int y; };

int twice(int v)
{
    int r = v * 2;
    return r;
}

void main()
{
    int i;
    for (i = 0; i < 3; i++) {
        count = twice(count + 1);
    }
    Print("%d", count);
}
"""

PDL = """\
proc add3( long a, long b, long * sum) do
   *sum=a+b;
end;
#long s;
#task/0;
start:
add3(4,5,&s);
printl("s=%ld", s);
halt;
"""

GDL = """\
MODULE m;
  DIGITAL$FLAG f [ INITIAL$VALUE = OFF ];
  INTEGER$VARIABLE n [ INITIAL$VALUE = 0 ];
  PROCEDURE p;
  DECLARE { STATUS OF f };
  BEGIN
    IF STATUS OF f = ON THEN
      VALUE OF n = VALUE OF n + 1;
    END$IF;
  END$PROCEDURE;
END$MODULE;
"""


def test_the_registry_lists_each_language_once_in_run_order():
    assert [lang.name for lang in LANGUAGES] == ["HMPL", "PDL", "GDL"]
    assert suffixes() == (".hmpl", ".pdl", ".gdl")
    assert language_of("a/B.HMPL") is language_named("HMPL") is language_named("hmpl")
    assert language_of("x.txt") is None
    with pytest.raises(KeyError):
        language_named("ST")


def test_line_tables_hold_the_statement_lines(tmp_path):
    hmpl = language_named("HMPL").line_table(str(tmp_path / "a.hmpl"), HMPL)
    assert sorted(hmpl.lines) == [6, 7, 13, 14, 16]
    assert hmpl.next_line(8) == 13 and hmpl.next_line(17) is None
    pdl = language_named("PDL").line_table(str(tmp_path / "a.pdl"), PDL)
    assert sorted(pdl.lines) == [2, 7, 8, 9]
    path = tmp_path / "a.gdl"
    path.write_text(GDL)
    gdl = language_named("GDL").line_table(str(path))
    assert sorted(gdl.lines) == [7, 8]


def test_symbols_are_the_declarations_with_their_places(tmp_path):
    path = str(tmp_path / "a.hmpl")
    found = {
        (s.name, s.kind, s.line, s.container) for s in language_named("HMPL").symbols(path, HMPL)
    }
    assert {("count", "variable", 1, None), ("pt", "struct", 2, None), ("x", "member", 2, "pt"),
            ("twice", "function", 4, None), ("v", "parameter", 4, "twice"),
            ("r", "variable", 6, "twice"), ("main", "function", 10, None),
            ("i", "variable", 12, "main")} <= found  # fmt: skip
    pdl = {(s.name, s.kind, s.line) for s in language_named("PDL").symbols("a.pdl", PDL)}
    assert {("add3", "procedure", 1), ("s", "variable", 4), ("#task/0", "task", 5),
            ("start", "label", 6)} <= pdl  # fmt: skip
    gdl_path = tmp_path / "a.gdl"
    gdl_path.write_text(GDL)
    gdl = [(s.name, s.kind, s.line) for s in language_named("GDL").symbols(str(gdl_path))]
    assert gdl == [("m", "module", 1), ("f", "object", 2), ("n", "object", 3),
                   ("p", "procedure", 4)]  # fmt: skip


def test_docs_carry_the_manuals_prototype_units_and_section():
    docs = language_named("HMPL").docs()
    move = docs["MoveAbs"]
    assert move.kind == "builtin" and move.signature.startswith(
        "int MoveAbs(int axis_id, double pos)"
    )
    assert move.section and move.implemented
    assert dict(move.params)["pos"].endswith("[mm or deg]")
    assert "MoveAbs" in move.markdown() and move.section in move.markdown()
    pi = docs["PI"]
    assert pi.kind == "constant" and abs(pi.value - 3.14159265) < 1e-6
    assert len([d for d in docs.values() if d.kind == "builtin"]) == 324


def test_compile_returns_the_program_or_the_diagnostics(tmp_path):
    hmpl = language_named("HMPL")
    ok = hmpl.compile([Source("a.hmpl", HMPL)], CompileRequest(DEFAULT_MACHINE))
    assert ok.program is not None
    bad = hmpl.compile(
        [Source("b.hmpl", "void main() { x = 1; }")], CompileRequest(DEFAULT_MACHINE)
    )
    assert bad.program is None
    assert [(d.severity, d.pos.line) for d in bad.diagnostics][:1] == [("error", 1)]
    assert "def " in hmpl.python_source(ok.program)


def test_a_language_refuses_input_it_cannot_place():
    with pytest.raises(LanguageInputError, match="task ids are 0..63"):
        language_named("HMPL").compile(
            [Source("a.hmpl", HMPL, task=64)], CompileRequest(DEFAULT_MACHINE)
        )


@pytest.mark.parametrize("lang", LANGUAGES, ids=lambda lang: lang.name)
def test_every_stage_dumps(lang, tmp_path):
    text = {"HMPL": HMPL, "PDL": PDL, "GDL": GDL}[lang.name]
    path = tmp_path / f"a{lang.suffixes[0]}"
    path.write_text(text)
    for stage in lang.stages:
        out, diagnostics = lang.dump(str(path), stage, {"task_id": 0})
        assert out.strip(), stage
        assert not [d for d in diagnostics if d.severity == "error"], stage
