"""Positions over the wire count UTF-16 code units (LSP's default encoding): a character
beyond the Basic Multilingual Plane (an emoji in a comment) counts two, in requests and
in every range the server answers."""

from __future__ import annotations

EMOJI = "\U0001f600"
TEXT = """int count = 0;
void main()
{
    /* EMOJI */ count = count + 1; nosuch = 2;
}
""".replace("EMOJI", EMOJI * 6)
LINE = TEXT.split("\n")[3]


def _units(chars: int) -> int:
    """UTF-16 code units of the first `chars` characters of LINE."""
    return len(LINE[:chars].encode("utf-16-le")) // 2


def test_positions_after_a_non_bmp_character_are_in_utf16_units(lsp, doc):
    uri = doc("emoji.hmpl", TEXT)
    lsp.open(uri, TEXT)
    start = LINE.index("nosuch")
    (diagnostic,) = lsp.diagnostics(uri)
    assert diagnostic["range"]["start"] == {"line": 3, "character": _units(start)}
    assert diagnostic["range"]["end"] == {"line": 3, "character": _units(start + 6)}

    first = LINE.index("count")
    at = _units(first)  # 6 units further than the character index: past `count`
    hover = lsp.at("textDocument/hover", uri, 3, at)
    assert "int count" in hover["contents"]["value"]
    refs = lsp.at("textDocument/references", uri, 3, at, context={"includeDeclaration": False})
    assert sorted(r["range"]["start"]["character"] for r in refs) == [
        _units(first),
        _units(LINE.index("count", first + 1)),
    ]
    assert lsp.at("textDocument/prepareRename", uri, 3, at) == {
        "start": {"line": 3, "character": _units(first)},
        "end": {"line": 3, "character": _units(first + 5)},
    }


def test_an_incremental_edit_after_a_non_bmp_character(lsp, doc):
    uri = doc("edit.hmpl", TEXT)
    lsp.open(uri, TEXT)
    lsp.diagnostics(uri)
    start = _units(LINE.index("nosuch"))
    cut = {"start": {"line": 3, "character": start}, "end": {"line": 3, "character": start + 6}}
    lsp.change(uri, 2, [{"range": cut, "text": "count"}])
    assert lsp.diagnostics(uri) == []


def test_a_form_feed_does_not_start_a_line(lsp, doc):
    text = "struct Pt { int x; double y; };\n\f\nvoid main() {\n    struct Pt p;\n    p.\n}\n"
    uri = doc("ff.hmpl", text)
    lsp.open(uri, text)
    lsp.diagnostics(uri)
    items = lsp.at("textDocument/completion", uri, 4, 6)["items"]
    assert [i["label"] for i in items] == ["x", "y"]
