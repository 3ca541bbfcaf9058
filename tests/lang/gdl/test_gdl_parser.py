"""GDL parser: AST dump of the example, precedence, case-insensitivity, generated docs."""

from __future__ import annotations

from pathlib import Path

import pytest

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.doc import readme_with_reference
from motionvm.lang.gdl.dump import dump_ast, dump_tokens
from motionvm.lang.gdl.lexer import tokenize
from motionvm.lang.gdl.parser import Parser
from motionvm.source.diagnostics import DiagnosticSink

PROGRAMS = Path(__file__).resolve().parents[2] / "programs" / "gdl"
GOLDEN = Path(__file__).resolve().parents[2] / "golden" / "gdl"


def test_gdl_ast_dump_of_the_example(monkeypatch: pytest.MonkeyPatch, golden) -> None:
    monkeypatch.chdir(PROGRAMS)
    sink = DiagnosticSink()
    golden(GOLDEN / "packer.ast", dump_ast("packer.gdl", sink))
    assert sink.items == []


def test_gdl_token_dump(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(PROGRAMS)
    lines = dump_tokens("packer.gdl", DiagnosticSink()).splitlines()
    assert lines[:4] == [
        "5:1 keyword MODULE",
        "5:8 ident packer_io",
        "5:17 delim ;",
        "7:3 keyword IO$BOARD",
    ]
    assert "11:22 string 'I/O board 1'" in lines
    assert lines[-1] == "86:1 eof"


def _expr(text: str) -> n.Expr:
    sink = DiagnosticSink()
    parser = Parser(tokenize("e.gdl", text, sink), sink)
    expr = parser._parse_expression()
    assert sink.items == [] and parser.tok.kind == "eof"
    return expr


def _shape(e: n.Expr) -> str:
    if isinstance(e, n.Binary):
        return f"({_shape(e.left)} {e.op} {_shape(e.right)})"
    if isinstance(e, n.Unary):
        return f"({e.op} {_shape(e.operand)})"
    if isinstance(e, n.StateRef):
        return f"{e.keyword.lower()}.{e.obj.name.text}"
    if isinstance(e, n.IntLit):
        return str(e.value)
    if isinstance(e, n.DigitalLit):
        return "ON" if e.value else "OFF"
    return type(e).__name__


@pytest.mark.parametrize(
    ("text", "shape"),
    [
        ("1 + 2 * 3", "(1 + (2 * 3))"),
        ("-1 - 2", "((- 1) - 2)"),
        ("(1 + 2) * 3", "((1 + 2) * 3)"),
        ("NOT STATUS OF x = ON", "(NOT (status.x = ON))"),
        ("ON OR OFF AND ON", "(ON OR (OFF AND ON))"),
        ("ON & OFF", "(ON AND OFF)"),
        ("VALUE OF a <= VALUE OF b + 1", "(value.a <= (value.b + 1))"),
        ("value of a <> 2", "(value.a <> 2)"),
        ("NOT NOT ON", "(NOT (NOT ON))"),
    ],
)
def test_gdl_expression_precedence(text: str, shape: str) -> None:
    assert _shape(_expr(text)) == shape


def test_gdl_case_insensitive_keywords_parse() -> None:
    sink = DiagnosticSink()
    text = "module m; integer$variable x [ initial$value = 1 ]; end$module;"
    tree = Parser(tokenize("c.gdl", text, sink), sink).parse_file("c.gdl")
    assert sink.items == []
    assert tree.modules[0].objects[0].type_kw == "INTEGER$VARIABLE"


def test_gdl_readme_reference_is_up_to_date() -> None:
    readme = (Path(__file__).resolve().parents[3] / "docs" / "lang" / "gdl.md").read_text()
    assert readme == readme_with_reference(readme), "run: python -m motionvm.lang.gdl.doc"
