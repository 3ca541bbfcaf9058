"""Garbage in, the server goes on: random text in every language, malformed frames,
requests about documents never opened or positions past the end."""

from __future__ import annotations

import random

import pytest

FEATURES = [
    "textDocument/hover",
    "textDocument/completion",
    "textDocument/signatureHelp",
    "textDocument/definition",
    "textDocument/references",
]


def garbage(seed: int) -> str:
    rnd = random.Random(seed)
    alphabet = "abcXYZ_$09 \t\n(){}[];:,.#\"'/*-+<>=|&!~@%^\\\u00e9\u4e2d\U0001f600"
    words = ["#include", "#define", "#if", "#endif", "MODULE", "END$MODULE", "PROCEDURE",
             "struct", "int", "goto", "while", "(", ")", "{", "}", "/*", "\"", "->", "."]  # fmt: skip
    out = []
    for _ in range(rnd.randint(50, 400)):
        out.append(rnd.choice(words) if rnd.random() < 0.3 else rnd.choice(alphabet))
    return "".join(out)


@pytest.mark.parametrize("suffix", [".hmpl", ".pdl", ".gdl"])
def test_garbage_text_never_kills_the_server(lsp, doc, suffix):
    for seed in range(6):
        text = garbage(seed)
        uri = doc(f"g{seed}{suffix}", "")
        lsp.open(uri, text)
        lsp.diagnostics(uri)
        lines = text.split("\n")
        rnd = random.Random(seed)
        for _ in range(8):
            line = rnd.randrange(len(lines) + 2)
            char = rnd.randrange(len(lines[line]) + 3) if line < len(lines) else 0
            for method in FEATURES:
                extra = {"context": {"includeDeclaration": True}} if "references" in method else {}
                answer = lsp.request(
                    method,
                    {"textDocument": {"uri": uri}, "position": {"line": line, "character": char},
                     **extra},
                )  # fmt: skip
                assert "error" not in answer, answer
        lsp.result("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
        cut = {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 3}}
        lsp.change(uri, 2, [{"range": cut, "text": '\u4e2d("'}])
        lsp.diagnostics(uri)


def test_malformed_messages_and_unknown_documents(lsp, doc):
    lsp.send_raw(b"Content-Length: 12\r\n\r\n{not json!!}")
    lsp.notify("textDocument/didOpen", {"textDocument": {"uri": 3}})  # wrong types
    lsp.notify("textDocument/didChange", {"textDocument": {"uri": "file:///nowhere.hmpl",
                                                          "version": 2}, "contentChanges": []})  # fmt: skip
    answer = lsp.request("textDocument/hover", {"textDocument": {"uri": "file:///x.hmpl"},
                                                "position": {"line": 0, "character": 0}})  # fmt: skip
    assert answer.get("result") is None
    answer = lsp.request("no/suchMethod", {})
    assert "error" in answer
    # still alive and working
    text = 'void main() { Print("hi"); }\n'
    uri = doc("alive.hmpl", text)
    lsp.open(uri, text)
    assert lsp.diagnostics(uri) == []
    hover = lsp.at("textDocument/hover", uri, 0, 15)
    assert "Print" in hover["contents"]["value"]
    # a text file that is no program: nothing to say, no error
    lsp.open("file:///tmp/notes.txt", "hello", language_id="plaintext")
    assert lsp.request("textDocument/hover", {"textDocument": {"uri": "file:///tmp/notes.txt"},
                                              "position": {"line": 0, "character": 1}})[
        "result"] is None  # fmt: skip


def test_no_internal_error_was_logged_on_garbage(lsp, doc):
    for seed in range(6, 10):
        for suffix in (".hmpl", ".pdl", ".gdl"):
            uri = doc(f"h{seed}{suffix}", "")
            lsp.open(uri, garbage(seed))
            lsp.diagnostics(uri)
            for line in range(3):
                lsp.at("textDocument/completion", uri, line, 2)
                lsp.at("textDocument/hover", uri, line, 2)
    errors = []
    while not lsp.notes.empty():
        note = lsp.notes.get()
        if note.get("method") in ("window/logMessage", "window/showMessage"):
            errors.append(note["params"]["message"])
    assert not [e for e in errors if "internal error" in e or "Error" in e], errors
