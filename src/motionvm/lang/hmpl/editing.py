"""What an editor sees inside an HMPL file: its names resolved, completions, error codes.

The declarations come from the syntax tree of the preprocessed file (task 0); the uses
from the file's own tokens before preprocessing, so that a name inside `#if 0`, a macro's
name and a use inside a macro's arguments all count. Scopes follow the braces: a local is
visible from its declaration to the end of its block, a parameter or label in its whole
function.
"""

from __future__ import annotations

import json
from functools import lru_cache
from importlib import resources

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.lexer import scan
from motionvm.lang.hmpl.parser import parse_file
from motionvm.lang.hmpl.tokens import KEYWORDS, Token
from motionvm.lang.index import Completion, SourceIndex, Symbol, resolve
from motionvm.lang.tools import nodes
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourceFile, text_lines

_NO_SPACE_BEFORE = {",", ")", "]", "[", ";"}
_NO_SPACE_AFTER = {"(", "["}


def _spell(toks: list[Token]) -> str:
    out = ""
    for i, t in enumerate(toks):
        glued = t.text == "(" and i and toks[i - 1].kind == "name"
        if (
            i
            and not glued
            and t.text not in _NO_SPACE_BEFORE
            and toks[i - 1].text not in _NO_SPACE_AFTER
        ):
            out += " "
        out += t.text
    return out.replace("* ", "*")


class _Tokens:
    """The file's tokens before preprocessing, with where each brace closes."""

    def __init__(self, path: str, text: str) -> None:
        self.toks = scan(SourceFile(path, text)).tokens
        self.lines = text_lines(text)
        self.where = {(t.pos.line, t.pos.col): i for i, t in enumerate(self.toks)}
        self.close: dict[int, int] = {}
        self.block_end: list[int] = [0] * len(self.toks)
        """Token index -> line where the innermost block around it ends (0: file level)."""
        stack: list[int] = []
        for i, t in enumerate(self.toks):
            if t.kind == "punct":
                if t.text in "({[":
                    stack.append(i)
                elif t.text in ")}]" and stack:
                    self.close[stack.pop()] = i
        last = self.toks[-1].pos.line if self.toks else 1
        braces: list[int] = []
        for i, t in enumerate(self.toks):
            if t.kind == "punct" and t.text == "{":
                braces.append(i)
            elif t.kind == "punct" and t.text == "}" and braces:
                braces.pop()
            if braces:
                end = self.close.get(braces[-1])
                self.block_end[i] = self.toks[end].pos.line if end is not None else last

    def index_of(self, pos) -> int | None:
        return self.where.get((pos.line, pos.col))

    def spell(self, start_pos, name_pos) -> str:
        """The tokens from `start_pos` through the declaration's name and, for a function,
        its parameter list."""
        a, b = self.index_of(start_pos), self.index_of(name_pos)
        if a is None or b is None or b < a or b - a > 40:
            return ""
        end = b
        if b + 1 < len(self.toks) and self.toks[b + 1].text == "(":
            end = self.close.get(b + 1, b)
        while end + 1 < len(self.toks) and self.toks[end + 1].text == "[":
            end = self.close.get(end + 1, end)
            if end - b > 40:
                break
        return _spell(self.toks[a : end + 1])

    def body_end(self, name_pos) -> int:
        """The last line of the function whose name is at `name_pos` (its closing brace)."""
        b = self.index_of(name_pos)
        if b is None or b + 1 >= len(self.toks) or self.toks[b + 1].text != "(":
            return 0
        i = self.close.get(b + 1)
        if i is None or i + 1 >= len(self.toks) or self.toks[i + 1].text != "{":
            return 0
        end = self.close.get(i + 1)
        return self.toks[end].pos.line if end is not None else self.toks[-1].pos.line


def build_index(path: str, text: str) -> SourceIndex:
    """Every name of an HMPL file's text resolved to its declaration."""
    tokens = _Tokens(path, text)
    tree = parse_file(path, task_id=0, sink=DiagnosticSink(), text=text)
    symbols = _symbols(path, tree, tokens) + _macros(path, tokens)
    symbols.sort(key=lambda s: (s.line, s.col))
    names: list[tuple[str, int, int]] = []
    members: list[tuple[str, int, int, int]] = []
    toks = tokens.toks
    for i, t in enumerate(toks):
        if t.kind != "name":
            continue
        before = toks[i - 1].text if i else ""
        if before in (".", "->"):
            members.append((t.text, t.pos.line, t.pos.col, i))
        elif before in ("struct", "union"):
            names.append(("struct " + t.text, t.pos.line, t.pos.col))
        else:
            names.append((t.text, t.pos.line, t.pos.col))
    index = resolve(path, text, symbols, names)
    index.occurrences = [_unprefixed(o) for o in index.occurrences]
    index.occurrences += _resolve_members(index, members, toks)
    index.__post_init__()
    return index


def _unprefixed(o):
    if o.name.startswith(("struct ", "union ")):
        from dataclasses import replace

        return replace(o, name=o.name.split(" ", 1)[1])
    return o


def _symbols(path: str, tree: n.TranslationUnit | None, tokens: _Tokens) -> list[Symbol]:
    out: list[Symbol] = []

    def add(name, kind, pos, start=None, container=None, end_line=0, detail=""):
        if pos.file != path:
            return
        if not detail and start is not None:
            detail = tokens.spell(start, pos)
        out.append(Symbol(name, kind, path, pos.line, pos.col, container, detail, end_line))

    def local_end(pos) -> int:
        i = tokens.index_of(pos)
        return tokens.block_end[i] if i is not None else 0

    for item in tree.items if tree is not None else ():
        decls = item.decls if isinstance(item, n.DeclStmt) else (item,)
        for d in decls:
            if isinstance(d, n.FuncDef):
                if d.body is None:
                    continue
                add(d.name, "function", d.pos, d.ret.pos, end_line=tokens.body_end(d.pos))
                for p in d.params:
                    add(p.name, "parameter", p.pos, p.type.pos, d.name)
                for node in nodes(d.body):
                    if isinstance(node, n.VarDecl):
                        add(node.name, "variable", node.pos, node.type.pos, d.name,
                            local_end(node.pos))  # fmt: skip
                    elif isinstance(node, n.Label):
                        add(node.name, "label", node.pos, container=d.name, detail=node.name)
                    elif isinstance(node, n.StructDef):  # (the walk meets each one once)
                        _struct(node, add, tokens)
            elif isinstance(d, n.VarDecl):
                add(d.name, "variable", d.pos, d.type.pos)
                _structs(d, add, tokens)
            elif isinstance(d, n.Typedef):
                add(d.name, "type", d.pos, d.type.pos)
                _structs(d, add, tokens)
            else:
                _structs(d, add, tokens)
    return out


def _structs(node, add, tokens: _Tokens) -> None:
    """The struct and union tags and members declared in `node`."""
    for s in nodes(node):
        if isinstance(s, n.StructDef):
            _struct(s, add, tokens)


def _struct(s: n.StructDef, add, tokens: _Tokens) -> None:
    """The tag and members of struct or union definition `s` (none without a tag)."""
    if not s.tag:
        return
    i = tokens.index_of(s.pos)
    toks = tokens.toks
    if i is None or i + 1 >= len(toks) or toks[i + 1].text != s.tag:
        return
    add(f"{s.kind} {s.tag}", "struct", toks[i + 1].pos, detail=f"{s.kind} {s.tag}")
    for f in s.fields:
        add(f.name, "member", f.pos, f.type.pos, f"{s.kind} {s.tag}")


def _macros(path: str, tokens: _Tokens) -> list[Symbol]:
    """`#define NAME` lines."""
    out = []
    toks = tokens.toks
    for i, t in enumerate(toks):
        if (
            t.text == "define"
            and i
            and toks[i - 1].text == "#"
            and i + 1 < len(toks)
            and toks[i + 1].kind in ("name", "keyword")
            and toks[i + 1].pos.line == t.pos.line
        ):
            name = toks[i + 1]
            detail = tokens.lines[t.pos.line - 1].strip() if t.pos.line <= len(tokens.lines) else ""
            out.append(Symbol(name.text, "macro", path, name.pos.line, name.pos.col,
                              detail=detail))  # fmt: skip
    return out


def _resolve_members(index: SourceIndex, members, toks: list[Token]):
    """Members after `.` and `->`: of the struct of the variable before them when that is
    known, else the only member of that name."""
    from motionvm.lang.index import Occurrence

    by_struct: dict[tuple[str | None, str], Symbol] = {}
    by_name: dict[str, list[Symbol]] = {}
    for s in index.symbols:
        if s.kind == "member":
            by_struct[(s.container, s.name)] = s
            by_name.setdefault(s.name, []).append(s)
    out = [Occurrence(s.name, s.line, s.col, s) for s in index.symbols if s.kind == "member"]
    for name, line, col, i in members:
        target = None
        struct = _struct_before(index, toks, i)
        if struct is not None:
            target = by_struct.get((struct, name))
        if target is None and len(by_name.get(name, ())) >= 1:
            target = by_name[name][0]
        out.append(Occurrence(name, line, col, target))
    return out


def _struct_before(index: SourceIndex, toks: list[Token], i: int) -> str | None:
    """The struct type (`struct T`) of the plain name before `.`/`->` at token i - 1."""
    if i < 2 or toks[i - 2].kind != "name":
        if i >= 2 and toks[i - 2].text == "]":  # a[k].x: the array's element
            depth = 0
            for j in range(i - 2, max(0, i - 60), -1):
                depth += {"]": 1, "[": -1}.get(toks[j].text, 0)
                if depth == 0:
                    return _struct_before(index, toks, j + 1) if j >= 1 else None
        return None
    left = toks[i - 2]
    occ = index.at(left.pos.line, left.pos.col)
    if occ is None or occ.symbol is None:
        return None
    return struct_of(occ.symbol.detail)


def struct_of(detail: str) -> str | None:
    """`struct T` of a declaration `struct T x` (or through its typedef: not followed)."""
    words = detail.replace("*", " ").split()
    for k, w in enumerate(words[:-1]):
        if w in ("struct", "union"):
            return f"{w} {words[k + 1]}"
    return None


# ------------------------------------------------------------------ completion


def member_completions(index: SourceIndex, line: int, col: int) -> list[Completion] | None:
    """Members, when the cursor follows `.` or `->` (None: it does not)."""
    text = index.line_text(line)[: col - 1]
    stripped = text.rstrip("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_")
    if not stripped.endswith((".", "->")):
        return None
    head = stripped[:-2] if stripped.endswith("->") else stripped[:-1]
    struct = None
    word = head.rstrip()
    k = len(word)
    while k and (word[k - 1].isalnum() or word[k - 1] == "_"):
        k -= 1
    if k < len(word):
        occ = index.at(line, k + 1)
        if occ is not None and occ.symbol is not None:
            struct = struct_of(occ.symbol.detail)
    members = [s for s in index.symbols if s.kind == "member"]
    if struct is not None and any(s.container == struct for s in members):
        members = [s for s in members if s.container == struct]
    seen = set()
    out = []
    for s in members:
        if s.name not in seen:
            seen.add(s.name)
            out.append(Completion(s.name, "member", s.detail, doc=f"member of `{s.container}`"))
    return out


@lru_cache(maxsize=1)
def keyword_completions() -> list[Completion]:
    return [Completion(k, "keyword") for k in sorted(KEYWORDS)]


# ------------------------------------------------------------------ error codes


@lru_cache(maxsize=1)
def _error_tables() -> tuple[dict[int, dict], dict[tuple[int, int], dict]]:
    data = json.loads(
        resources.files("motionvm.data").joinpath("hmpl_errors.json").read_text("utf-8")
    )
    system: dict[int, dict] = {}
    per_id: dict[tuple[int, int], dict] = {}
    for e in data:
        if e["table"] == "system":
            system[int(e["code"], 16)] = e
        elif e["table"] in ("axis", "group"):
            prefix = 0x83 if e["table"] == "axis" else 0x82
            per_id[(prefix, int(e["code"][-4:], 16))] = e
    return system, per_id


def error_code_doc(word: str) -> str | None:
    """Markdown naming the chapter 18 error code written as `word` (hex or decimal, as
    `motionvm errors` reads it), or None if it is none."""
    try:
        value = int(word, 16) if word.lower().lstrip("-").startswith("0x") else int(word)
    except ValueError:
        return None
    if value == 0 or not -(2**31) <= value < 2**32:
        return None
    value &= 0xFFFFFFFF
    system, per_id = _error_tables()
    entry = system.get(value)
    owner = ""
    if entry is None:
        entry = per_id.get((value >> 24, value & 0xFFFF))
        if entry is None:
            return None
        owner = f" ({entry['table']} {(value >> 16) & 0xFF})"
    return (
        f"**{entry['name']}**{owner}: error code `0x{value:08x}`\n\n{entry['desc']}\n\n"
        f"Manual {entry['section']}"
    )
