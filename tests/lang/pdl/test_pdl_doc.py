"""docs/lang/pdl.md is generated from the parser and the system-variable catalog."""

from pathlib import Path

from motionvm.lang.pdl.doc import render

DOC = Path(__file__).resolve().parents[3] / "docs" / "lang" / "pdl.md"


def test_pdl_doc_is_current():
    assert DOC.read_text(encoding="utf-8") == render(), "run: python -m motionvm.lang.pdl.doc"
