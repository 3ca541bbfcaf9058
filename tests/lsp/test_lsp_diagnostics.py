"""`motionvm lsp` on the wire: its capabilities, and diagnostics exactly as `motionvm check`
reports them, after opening and after edits, of unsaved text, through includes and
preprocessor conditionals."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

HEADLINE = re.compile(r"^(.*):(\d+):(\d+): (error|warning): (.*)$")

HMPL_BAD = """void main() {
    int x;
    Print("%d", y);
}
"""
PDL_BAD = """#long p;
#task/0;
p = q;
halt;
"""
GDL_BAD = """MODULE m;
  DIGITAL$FLAG f [ INITIAL$VALUE = OFF ];
  PROCEDURE p;
  DECLARE { STATUS OF f };
  BEGIN
    STATUS OF nothing = ON;
  END$PROCEDURE;
END$MODULE;
"""


def check_cli(path: str) -> list[tuple[str, int, int, str, str]]:
    """(file, line, col, severity, message) of each diagnostic `motionvm check` prints."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(Path(__file__).resolve().parents[2] / "src")
    out = subprocess.run(
        [sys.executable, "-m", "motionvm", "check", path],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    found = []
    for line in out.stderr.splitlines():
        m = HEADLINE.match(line)
        if m:
            found.append((m[1], int(m[2]), int(m[3]), m[4], m[5]))
    return found


def as_check(diags: list[dict], path: str) -> list[tuple[str, int, int, str, str]]:
    sev = {1: "error", 2: "warning"}
    return [
        (path, d["range"]["start"]["line"] + 1, d["range"]["start"]["character"] + 1,
         sev[d["severity"]], d["message"])
        for d in diags
    ]  # fmt: skip


def test_capabilities(tmp_path):
    from lsp_client import LspClient

    client = LspClient(cwd=tmp_path)
    try:
        caps = client.initialize()["capabilities"]
    finally:
        assert client.close() == 0
    assert caps["textDocumentSync"]["change"] == 2  # incremental
    assert caps["hoverProvider"]
    assert set(caps["signatureHelpProvider"]["triggerCharacters"]) == {"(", ","}
    assert "." in caps["completionProvider"]["triggerCharacters"]
    for key in ("definitionProvider", "referencesProvider", "documentSymbolProvider"):
        assert caps[key]
    assert caps["renameProvider"]


@pytest.mark.parametrize(
    "name, text",
    [("bad.hmpl", HMPL_BAD), ("bad.pdl", PDL_BAD), ("bad.gdl", GDL_BAD)],
)
def test_diagnostics_are_what_check_reports(lsp, doc, tmp_path, name, text):
    uri = doc(name, text)
    path = str(tmp_path / name)
    lsp.open(uri, text)
    diags = lsp.diagnostics(uri)
    expected = check_cli(path)
    assert expected, "the program has errors"
    assert as_check(diags, path) == expected
    assert all(d["source"] == "motionvm" for d in diags)
    # the range covers the token: `y` in HMPL, `q` in PDL, `nothing` in GDL
    first = diags[-1] if name.endswith(".hmpl") else diags[0]
    start, end = first["range"]["start"], first["range"]["end"]
    assert start["line"] == end["line"] and end["character"] > start["character"]


def test_warnings_have_severity_2(lsp, doc):
    uri = doc("w.hmpl", HMPL_BAD)
    lsp.open(uri, HMPL_BAD)
    diags = lsp.diagnostics(uri)
    assert [(d["severity"], d["message"]) for d in diags] == [
        (2, "unused variable 'x'"),
        (1, "'y' undeclared (did you mean 'Y'?)"),
    ]
    x = diags[0]["range"]
    assert (x["start"]["character"], x["end"]["character"]) == (8, 9)


def test_edits_break_and_fix_a_file(lsp, doc):
    good = 'void main() {\n    int n = 1;\n    Print("%d", n);\n}\n'
    uri = doc("e.hmpl", good)
    lsp.open(uri, good)
    assert lsp.diagnostics(uri) == []
    # an incremental edit: `n` -> `m` in the Print call
    rng = {"start": {"line": 2, "character": 16}, "end": {"line": 2, "character": 17}}
    lsp.change(uri, 2, [{"range": rng, "text": "m"}])
    broken = lsp.diagnostics(uri)
    assert [d["message"] for d in broken] == ["unused variable 'n'", "'m' undeclared"]
    lsp.change(uri, 3, [{"range": rng, "text": "n"}])
    assert lsp.diagnostics(uri) == []
    # a full-text change works too
    lsp.change(uri, 4, [{"text": good.replace("int n = 1;", "int n = ;")}])
    assert [d["message"] for d in lsp.diagnostics(uri)] == ["expected expression before ';'"]


def test_an_unsaved_buffer_is_checked_not_the_file(lsp, doc, tmp_path):
    on_disk = 'void main() {\n    Print("ok");\n}\n'
    uri = doc("u.hmpl", on_disk)
    lsp.open(uri, on_disk.replace('"ok"', "undeclared_name"))
    diags = lsp.diagnostics(uri)
    assert [d["message"] for d in diags] == ["'undeclared_name' undeclared"]
    assert (tmp_path / "u.hmpl").read_text() == on_disk


def test_untitled_buffers_are_checked_by_language_id(lsp):
    uri = "untitled:Untitled-1"
    lsp.open(uri, "long p;\n", language_id="pdl")
    assert [d["message"] for d in lsp.diagnostics(uri)] == [
        "unexpected keyword 'long' at the start of a statement"
    ]


def test_includes_and_conditionals_resolve_as_in_check(lsp, doc, tmp_path):
    doc("defs.h", "#define SPEED 100\n#define BROKEN (1 +\n")
    main = (
        '#include "defs.h"\n'
        "void main() {\n"
        "#if _TASKID_ == 0\n"
        "    int v = SPEED;\n"
        "#else\n"
        "    int v = NOT_DECLARED_ANYWHERE;\n"
        "#endif\n"
        '    Print("%d", v);\n'
        "}\n"
    )
    uri = doc("inc.hmpl", main)
    lsp.open(uri, main)
    assert as_check(lsp.diagnostics(uri), str(tmp_path / "inc.hmpl")) == check_cli(
        str(tmp_path / "inc.hmpl")
    )
    # an error inside a header is published on the header's uri, and cleared with it
    (tmp_path / "bad.h").write_text("int = 3;\n")
    text = main.replace('"defs.h"', '"bad.h"')
    lsp.change(uri, 2, [{"text": text}])
    header = (tmp_path / "bad.h").resolve().as_uri()
    by_uri = {}
    for _ in range(2):
        note = lsp.next_publish()
        by_uri[note["uri"]] = note["diagnostics"]
    (tmp_path / "inc2.hmpl").write_text(text)
    expected = check_cli(str(tmp_path / "inc2.hmpl"))
    assert {f for f, *_ in expected} == {str(tmp_path / "bad.h")}
    assert as_check(by_uri[header], str(tmp_path / "bad.h")) == expected
    assert by_uri[uri] == []
    lsp.change(uri, 3, [{"text": main}])
    cleared = {}
    for _ in range(2):
        note = lsp.next_publish()
        cleared[note["uri"]] = note["diagnostics"]
    assert cleared == {uri: [], header: []}
