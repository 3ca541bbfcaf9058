"""`motionvm lsp` on PDL and GDL files: every feature over the wire."""

from __future__ import annotations

PDL = """#long count;
#long target;
#task/0;
start:
count = 0;
target = X_vel_max;
again:
count += 1;
if (count < 10) goto again;
call start;
halt;
"""

GDL = """MODULE io;
  DIGITAL$INPUT button [ BOARD$NAME = board, CHANNEL = 1 ];
  IO$BOARD board [ SLOT = 1, INPUT$MODULE = PRESENT ];
  DIGITAL$FLAG run [ INITIAL$VALUE = OFF ];
  PROCEDURE watch;
  DECLARE { STATUS OF button };
  BEGIN
    STATUS OF run = STATUS OF button;
  END$PROCEDURE;
END$MODULE;
"""


def spots(locations):
    return sorted((x["range"]["start"]["line"], x["range"]["start"]["character"])
                  for x in locations)  # fmt: skip


def test_pdl(lsp, doc):
    uri = doc("d.pdl", PDL)
    lsp.open(uri, PDL)
    assert lsp.diagnostics(uri) == []
    # hover: a variable's declaration, a system variable's description
    assert "long count" in lsp.at("textDocument/hover", uri, 4, 1)["contents"]["value"]
    sysvar = lsp.at("textDocument/hover", uri, 5, 11)["contents"]["value"]
    assert "X_vel_max" in sysvar and "velocity" in sysvar
    labels = {i["label"]: i for i in lsp.at("textDocument/completion", uri, 8, 0)["items"]}
    for name in ("count", "target", "start", "again", "goto", "while", "X_vel_max"):
        assert name in labels, name
    assert labels["goto"]["kind"] == 14  # Keyword
    # labels and variables: definition, references, rename
    assert spots(lsp.at("textDocument/definition", uri, 8, 23)) == [(6, 0)]
    refs = lsp.at("textDocument/references", uri, 9, 6, context={"includeDeclaration": True})
    assert spots(refs) == [(3, 0), (9, 5)]
    edit = lsp.at("textDocument/rename", uri, 7, 1, newName="n")
    assert spots(edit["changes"][uri]) == [(0, 6), (4, 0), (7, 0), (8, 4)]
    symbols = lsp.result("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    names = [s["name"] for s in symbols]
    assert "#task/0" in names and "start" in names and "again" in names
    help_ = lsp.at("textDocument/signatureHelp", uri, 8, 4)
    assert help_ is None


def test_gdl(lsp, doc):
    uri = doc("a.gdl", GDL)
    lsp.open(uri, GDL)
    assert lsp.diagnostics(uri) == []
    hover = lsp.at("textDocument/hover", uri, 1, 20)["contents"]["value"]
    assert "DIGITAL$INPUT button" in hover
    kind = lsp.at("textDocument/hover", uri, 3, 4)["contents"]["value"]
    assert "DIGITAL$FLAG" in kind
    labels = {i["label"]: i for i in lsp.at("textDocument/completion", uri, 7, 4)["items"]}
    for name in ("DIGITAL$INPUT", "STATUS", "button", "board", "run", "watch", "io"):
        assert name in labels, name
    assert labels["DIGITAL$INPUT"]["kind"] == 7  # Class: an object kind
    assert labels["STATUS"]["kind"] == 10  # Property: an attribute
    # objects (case-insensitive, as GDL reads names), definition and rename
    assert spots(lsp.at("textDocument/definition", uri, 1, 39)) == [(2, 11)]
    refs = lsp.at("textDocument/references", uri, 5, 25, context={"includeDeclaration": True})
    assert spots(refs) == [(1, 16), (5, 22), (7, 30)]
    edit = lsp.at("textDocument/rename", uri, 4, 13, newName="observe")
    assert spots(edit["changes"][uri]) == [(4, 12)]
    symbols = lsp.result("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    assert [s["name"] for s in symbols] == ["io"]
    children = [c["name"] for c in symbols[0]["children"]]
    assert children == ["button", "board", "run", "watch"]


def _quiet(lsp, uri, spots_inside, spot_in_code):
    for line, col in spots_inside:
        assert lsp.at("textDocument/completion", uri, line, col)["items"] == [], (line, col)
    assert lsp.at("textDocument/completion", uri, *spot_in_code)["items"]


def test_no_completion_inside_a_pdl_comment_or_string(lsp, doc):
    text = '#long count;\n#task/0;\n// see co\n/* co\n co */ printl("co %ld", count);\nco\nhalt;\n'
    uri = doc("q.pdl", text)
    lsp.open(uri, text)
    lsp.diagnostics(uri)
    # after `co` in the line comment, both lines of the block comment and the string
    _quiet(lsp, uri, ((2, 9), (3, 5), (4, 3), (4, 18)), (5, 2))


def test_no_completion_inside_a_gdl_comment_or_string(lsp, doc):
    text = GDL.replace("BEGIN", "BEGIN | see ru\n    ru |").replace(
        "STATUS OF run = STATUS OF button;", "STATUS OF run = STATUS OF button; | 'ru' |"
    )
    uri = doc("q.gdl", text)
    lsp.open(uri, text)
    lsp.diagnostics(uri)
    lines = text.splitlines()
    comment = next(i for i, x in enumerate(lines) if "| see ru" in x)
    assert lines[comment + 1] == "    ru |"
    status = next(i for i, x in enumerate(lines) if "'ru'" in x)
    quoted = lines[status].index("'ru'") + 3  # (inside the comment's quotes: a comment)
    inside = ((comment, len(lines[comment])), (comment + 1, 6), (status, quoted))
    _quiet(lsp, uri, inside, (status, 8))


def test_a_gdl_string_is_quiet_too(lsp, doc):
    text = GDL.replace("END$PROCEDURE;", "    VALUE OF run = 'ru';\n  END$PROCEDURE;")
    uri = doc("s.gdl", text)
    lsp.open(uri, text)
    lsp.diagnostics(uri)
    lines = text.splitlines()
    line = next(i for i, x in enumerate(lines) if "'ru'" in x)
    _quiet(lsp, uri, ((line, lines[line].index("'ru'") + 3),), (line, 8))
