"""`motionvm lsp` on an HMPL file: hover, completion, signature help, definition,
references, rename and the outline, over the wire."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

PROGRAM = """#define N 4
struct Pt { int x; double y; };
struct Pt origin;
int count = 0;

int add(int a, int b) {
    int s = a + b;
    origin.x = s;
    return s;
}

void main() {
    struct Pt p;
    p.y = 2.0;
    int s = add(1, N);
    MoveAbs(0, 10.0);
    if (s != 0x83000136) Print("%d", count);
    p.
}
"""


def open_program(lsp, doc):
    uri = doc("prog.hmpl", PROGRAM)
    lsp.open(uri, PROGRAM)
    lsp.diagnostics(uri)
    return uri


def prototype(name: str) -> str:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(Path(__file__).resolve().parents[2] / "src")
    out = subprocess.run(
        [sys.executable, "-m", "motionvm", "builtins", name, "--json"],
        capture_output=True, text=True, env=env, timeout=60, check=True,
    )  # fmt: skip
    return json.loads(out.stdout)["prototype"]


def test_hover(lsp, doc):
    uri = open_program(lsp, doc)
    builtin = lsp.at("textDocument/hover", uri, 15, 6)["contents"]
    assert builtin["kind"] == "markdown"
    text = builtin["value"]
    assert prototype("MoveAbs") in text
    assert "Move an axis to an absolute target position." in text
    assert "`pos`" in text and "[mm or deg]" in text  # parameters with units
    assert "Returns:" in text and "5.2.4" in text  # return value, manual section
    user = lsp.at("textDocument/hover", uri, 16, 38)["contents"]["value"]
    assert "int count" in user  # a global's declaration
    code = lsp.at("textDocument/hover", uri, 16, 14)["contents"]["value"]
    assert "eERR_AXIS_CMD_INVALID_POS" in code and "axis 0" in code
    const = lsp.at("textDocument/hover", uri, 14, 20)["contents"]["value"]
    assert "#define N 4" in const
    assert lsp.at("textDocument/hover", uri, 4, 0) is None  # a blank line


def test_hover_of_a_constant_shows_its_value(lsp, doc):
    text = "void main() { int a = AXIS_STATE_ENABLE; }\n"
    uri = doc("c.hmpl", text)
    lsp.open(uri, text)
    lsp.diagnostics(uri)
    hover = lsp.at("textDocument/hover", uri, 0, 25)
    assert hover is None or "=" in hover["contents"]["value"]


def test_completion(lsp, doc):
    uri = open_program(lsp, doc)
    items = lsp.at("textDocument/completion", uri, 15, 4)["items"]
    by_label = {i["label"]: i for i in items}
    move = by_label["MoveAbs"]
    assert move["kind"] == 3  # Function
    assert move["detail"] == prototype("MoveAbs")
    assert move["insertText"] == "MoveAbs(${1:axis_id}, ${2:pos})"
    assert move["insertTextFormat"] == 2  # snippet
    for name in ("count", "origin", "add", "main", "N", "s", "p", "Pt", "while"):
        assert name in by_label, name
    assert "a" not in by_label  # a parameter of another function
    assert by_label["add"]["detail"] == "int add(int a, int b)"
    members = lsp.at("textDocument/completion", uri, 17, 6)["items"]
    assert sorted(i["label"] for i in members) == ["x", "y"]
    assert {i["kind"] for i in members} == {5}  # Field


def test_no_completion_inside_a_comment_or_a_literal(lsp, doc):
    text = 'struct Pt { int x; };\nvoid main() {\n    struct Pt p; // see p.\n    /* p.\n  p. */ Print("p.");\n    p.\n}\n'
    uri = doc("quiet.hmpl", text)
    lsp.open(uri, text)
    lsp.diagnostics(uri)
    for line, col in ((2, 26), (3, 9), (4, 4), (4, 17)):  # after a `p.` in each
        assert lsp.at("textDocument/completion", uri, line, col)["items"] == [], (line, col)
    members = lsp.at("textDocument/completion", uri, 5, 6)["items"]  # the code's `p.`
    assert [i["label"] for i in members] == ["x"]
    assert lsp.at("textDocument/completion", uri, 4, 12)["items"]  # after the comment


def test_signature_help(lsp, doc):
    uri = open_program(lsp, doc)
    help_ = lsp.at("textDocument/signatureHelp", uri, 15, 15)
    sig = help_["signatures"][0]
    assert sig["label"] == prototype("MoveAbs")
    assert help_["activeParameter"] == 1
    first = lsp.at("textDocument/signatureHelp", uri, 15, 12)
    assert first["activeParameter"] == 0
    start, end = sig["parameters"][1]["label"]
    assert sig["label"][start:end] == "double pos"
    user = lsp.at("textDocument/signatureHelp", uri, 14, 16)
    assert user["signatures"][0]["label"] == "int add(int a, int b)"
    assert user["activeParameter"] == 0
    assert lsp.at("textDocument/signatureHelp", uri, 13, 6) is None  # not in a call


def test_definition_references_rename(lsp, doc):
    uri = open_program(lsp, doc)

    def spots(locations):
        return sorted((x["range"]["start"]["line"], x["range"]["start"]["character"])
                      for x in locations)  # fmt: skip

    # a local: `s` of add, not main's `s`
    assert spots(lsp.at("textDocument/definition", uri, 8, 12)) == [(6, 8)]
    refs = lsp.at("textDocument/references", uri, 8, 12, context={"includeDeclaration": True})
    assert spots(refs) == [(6, 8), (7, 15), (8, 11)]
    # a global, a function, a macro, a struct type and a member
    assert spots(lsp.at("textDocument/definition", uri, 16, 38)) == [(3, 4)]
    assert spots(lsp.at("textDocument/definition", uri, 14, 13)) == [(5, 4)]
    assert spots(lsp.at("textDocument/definition", uri, 14, 19)) == [(0, 8)]
    assert spots(lsp.at("textDocument/definition", uri, 12, 12)) == [(1, 7)]
    assert spots(lsp.at("textDocument/definition", uri, 13, 6)) == [(1, 26)]
    refs = lsp.at("textDocument/references", uri, 7, 12, context={"includeDeclaration": False})
    assert spots(refs) == [(7, 11)]
    edit = lsp.at("textDocument/rename", uri, 3, 5, newName="total")
    changes = edit["changes"][uri]
    assert spots(changes) == [(3, 4), (16, 37)]
    assert {c["newText"] for c in changes} == {"total"}
    edit = lsp.at("textDocument/rename", uri, 1, 8, newName="Point")
    assert spots(edit["changes"][uri]) == [(1, 7), (2, 7), (12, 11)]
    assert lsp.at("textDocument/definition", uri, 15, 6) is None  # a built-in


def test_a_local_struct_s_members_are_renamed_once_each(lsp, doc):
    # a struct defined in a block inside a loop of a function: its tag and members were
    # indexed once per statement around it, and a rename sent each edit three times
    text = (
        "void main() {\n    int i;\n    for (i = 0; i < 2; i++) {\n        {\n"
        "            struct Q { int a; } q;\n            q.a = i;\n        }\n    }\n}\n"
    )
    uri = doc("local.hmpl", text)
    lsp.open(uri, text)
    assert lsp.diagnostics(uri) == []
    edit = lsp.at("textDocument/rename", uri, 5, 14, newName="count")
    starts = [(c["range"]["start"]["line"], c["range"]["start"]["character"])
              for c in edit["changes"][uri]]  # fmt: skip
    assert sorted(starts) == [(4, 27), (5, 14)]


def test_document_symbols(lsp, doc):
    uri = open_program(lsp, doc)
    symbols = lsp.result("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    names = [(s["name"], s["kind"]) for s in symbols]
    assert ("add", 12) in names and ("main", 12) in names  # functions
    assert ("count", 13) in names and ("origin", 13) in names  # globals
    assert "s" not in [n for n, _ in names]  # locals are not in the outline
