"""docs/lang/hmpl.md is generated from the parser's BNF lines and must be current."""

from pathlib import Path

from motionvm.lang.hmpl.grammar_doc import PARSER, render

DOC = Path(__file__).resolve().parents[3] / "docs" / "lang" / "hmpl.md"


def test_grammar_doc_is_current():
    expected = render(PARSER.read_text(encoding="utf-8"))
    assert DOC.read_text(encoding="utf-8") == expected, (
        "run: python -m motionvm.lang.hmpl.grammar_doc"
    )


def test_every_parse_method_has_a_bnf_line():
    lines = PARSER.read_text(encoding="utf-8").splitlines()
    for i, line in enumerate(lines):
        if line.strip().startswith("def _parse_"):
            above = [x.strip() for x in lines[max(0, i - 6) : i]]
            assert any(x.startswith("# BNF:") for x in above), line.strip()
