"""HMPL parser: preprocessed tokens to the AST of `nodes.py`, by recursive descent.

One `_parse_<rule>` method per grammar rule, each with its `# BNF:` line (the
language reference in docs/lang/hmpl.md is generated from them). Syntax errors are
reported to the sink and the parser resynchronises at the next statement or
declaration boundary, so one run reports many errors and never raises for bad input.

Node positions: statements and declarations sit at their first token; `Binary`,
`Assign`, `Unary`, `Postfix` and `Cond` at their operator; `Index` at '[';
`Member` at the member name; `Call` at the callee; `Cast` at its '('.
Struct/union definitions are allowed at file scope only; an anonymous one has
tag '' and a TypeRef base of plain 'struct'/'union' with `struct_def` set.
`extern` variable declarations declare nothing (task 0's globals are visible
everywhere) and are left out of the tree. Enumerators become `IntLit`s where they
are used (an `enum` type is 'int32_t'), so no enum reaches the later stages.
`T a[] = init` gets its first dimension from the initializer as an `IntLit`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from operator import attrgetter
from typing import ClassVar

from motionvm.lang.gc_hold import gc_held
from motionvm.lang.hmpl import check_memo
from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.preprocess import preprocess
from motionvm.lang.hmpl.tokens import BINARY_PREC, Token
from motionvm.source.deep import run_deep
from motionvm.source.diagnostics import DiagnosticSink, TooManyErrors
from motionvm.source.files import SourceFile, SourcePos
from motionvm.source.suggest import did_you_mean

PREDEFINED_TYPES = ("Timer", "Data_t")
INTN_TYPES = frozenset(
    ["int8_t", "uint8_t", "int16_t", "uint16_t", "int32_t", "uint32_t", "int64_t", "uint64_t"]
)
BASIC_WORDS = frozenset(
    ["void", "char", "short", "int", "long", "float", "double", "signed", "unsigned"]
)
QUALIFIERS = frozenset(("const", "volatile"))
STORAGE = frozenset(("static", "extern"))
DECL_START = (
    BASIC_WORDS | INTN_TYPES | QUALIFIERS | STORAGE | {"struct", "union", "enum", "typedef"}
)
TYPE_START = BASIC_WORDS | INTN_TYPES | QUALIFIERS | {"struct", "union", "enum"}
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1
SCALAR_BASES = INTN_TYPES | {"char", "float", "double"}

ASSIGN_OPS = frozenset(["=", "+=", "-=", "*=", "/=", "%=", "<<=", ">>=", "&=", "|=", "^="])
UNARY_OPS = frozenset(["-", "+", "!", "~", "*", "&"])
POSTFIX_START = frozenset(["[", "(", ".", "->", "++", "--"])
MAX_NESTING = 2048
"""Levels of nesting the parser follows: each block, statement, parenthesis, unary
operator and initializer brace is one (so about 1,000 nested blocks)."""
MAX_OPERATORS = 50_000
"""Binary operators of one precedence level in a row (`a + b + ...`): each is a level of
the tree the compiler walks."""
_text = attrgetter("text")
_kind = attrgetter("kind")


def _canonical_table() -> dict[tuple[str, ...], str]:
    spellings = {
        "char": ("char", "signed char"),
        "uint8_t": ("unsigned char",),
        "int16_t": ("short", "short int", "signed short", "signed short int"),
        "uint16_t": ("unsigned short", "unsigned short int"),
        "int32_t": (
            "int",
            "signed",
            "signed int",
            "long",
            "long int",
            "signed long",
            "signed long int",
        ),
        "uint32_t": ("unsigned", "unsigned int", "unsigned long", "unsigned long int"),
        "int64_t": ("long long", "long long int", "signed long long", "signed long long int"),
        "uint64_t": ("unsigned long long", "unsigned long long int"),
        "float": ("float",),
        "double": ("double", "long double"),
        "void": ("void",),
    }
    return {tuple(sorted(s.split())): base for base, ss in spellings.items() for s in ss}


CANONICAL = _canonical_table()


class _TooDeep(Exception):
    """A nest past MAX_NESTING: parsing of the file stops (the error is reported)."""


class _Fail(Exception):
    """A syntax error was reported; unwind to the nearest recovery point."""


def parse_file(
    path: str,
    *,
    task_id: int,
    sink: DiagnosticSink,
    text: str | None = None,
    included: list[SourceFile] | None = None,
    function_keys: bool = False,
) -> n.TranslationUnit | None:
    """Preprocess and parse one task file; None when the file cannot be read. `included`
    receives the files its `#include`s read; `function_keys`: see `parse`."""
    if text is None:
        try:
            text = SourceFile.read(path).text
        except OSError as e:
            sink.error(SourcePos(path, 1, 1), f"cannot read '{path}': {e.strerror or e}")
            return None
    with gc_held(promote=False):
        tokens = preprocess(path, task_id=task_id, sink=sink, text=text, included=included)
        return parse(tokens, sink, function_keys)


def parse(
    tokens: list[Token], sink: DiagnosticSink, function_keys: bool = False
) -> n.TranslationUnit:
    """Parse preprocessed tokens (ending with 'eof'); errors go to `sink`. With
    `function_keys` the unit carries each function definition's key (`check_memo`)."""
    with gc_held(promote=False):
        parser = Parser(tokens, sink)
        if function_keys:
            parser.function_spans = []
        tu = run_deep(parser.run)
        if function_keys:
            tu.function_keys = check_memo.function_keys(
                parser.toks, parser.keys, parser.function_spans
            )
        return tu


def _end_of(t: Token) -> SourcePos:
    """The position just after a token (where a missing ';' belongs)."""
    return SourcePos(t.pos.file, t.pos.line, t.pos.col + len(t.text))


def _describe(t: Token) -> str:
    return "end of file" if t.kind == "eof" else f"'{t.text}'"


class Parser:
    """Recursive-descent parser over a token list; `run` parses a whole task."""

    def __init__(self, tokens: list[Token], sink: DiagnosticSink) -> None:
        if not tokens or tokens[-1].kind != "eof":
            last = tokens[-1].pos if tokens else SourcePos("<input>", 1, 1)
            tokens = [*tokens, Token("eof", "", last)]
        self.toks = tokens
        # the grammar looks at token texts: a keyword or punctuator is its text, and no
        # name or literal can spell one; `kinds` tells names and literals apart
        self.keys = list(map(_text, tokens))
        self.kinds = list(map(_kind, tokens))
        self.i = 0
        self.sink = sink
        self.typedefs: set[str] = set(PREDEFINED_TYPES)
        self.block_typedefs: list[str] = []  # names typedef'd in the open blocks
        # typedef names an ordinary identifier of an open block hides (`struct s s;`)
        self.hidden_typedefs: list[str] = []
        # enum constants are replaced by their values as they are parsed
        self.enumerators: dict[str, int] = {}
        self.items: list = []
        self.new_structs: list[n.StructDef] = []
        self.depth = 0
        # (FuncDef, first token, after its last, parser state): kept checks' keys
        self.function_spans: list[tuple] | None = None

    def run(self) -> n.TranslationUnit:
        try:
            self._parse_translation_unit()
        except (TooManyErrors, _TooDeep):
            pass
        except RecursionError:  # pragma: no cover - MAX_NESTING keeps us well below
            self.sink.error(
                self.toks[min(self.i, len(self.toks) - 1)].pos, "program nested too deeply"
            )
        return n.TranslationUnit(SourcePos(self.toks[-1].pos.file, 1, 1), tuple(self.items))

    # ------------------------------------------------------------ token helpers

    def _tok(self) -> Token:
        return self.toks[self.i]

    def _peek_key(self, k: int = 1) -> str:
        j = self.i + k
        return self.keys[j] if j < len(self.keys) else ""

    def _peek_kind(self, k: int = 1) -> str:
        j = self.i + k
        return self.kinds[j] if j < len(self.kinds) else "eof"

    def _advance(self) -> Token:
        t = self.toks[self.i]
        if self.keys[self.i] != "":
            self.i += 1
        return t

    def _accept(self, key: str) -> bool:
        if self.keys[self.i] == key:
            self.i += 1
            return True
        return False

    def _expect(self, key: str, context: str = "") -> Token:
        if self.keys[self.i] == key:
            t = self.toks[self.i]
            self.i += 1
            return t
        if key == ";" and self.i > 0:
            prev = self.toks[self.i - 1]
            self._error(_end_of(prev), f"expected ';' {context}".rstrip())
            t = self.toks[self.i]
            if t.pos.line != prev.pos.line or self.keys[self.i] in ("}", ""):
                return t  # the line just lacks its ';': carry on as if it were there
        elif self.i > 0 and self.toks[self.i].pos.line != self.toks[self.i - 1].pos.line:
            # the line ended too early: point at its end, not at the next line
            self._error(_end_of(self.toks[self.i - 1]), f"expected '{key}' {context}".rstrip())
        else:
            t = self._tok()
            self._error(t.pos, f"expected '{key}' {context or 'before ' + _describe(t)}")
        raise _Fail

    def _error(self, pos: SourcePos, message: str) -> None:
        self.sink.error(pos, message)

    def _fail_here(self, message: str) -> _Fail:
        self._error(self._tok().pos, message)
        return _Fail()

    def _enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            self._error(
                self._tok().pos,
                f"nesting deeper than {MAX_NESTING} levels (the limit of HMPL); the rest of"
                " the file is not parsed",
            )
            raise _TooDeep  # no recovery inside such a nest: it would only add errors

    def _is_type_start(self, j: int) -> bool:
        k = self.keys[j]
        return k in TYPE_START or (self.kinds[j] == "name" and self.toks[j].text in self.typedefs)

    def _starts_declaration(self) -> bool:
        k = self.keys[self.i]
        return k in DECL_START or (
            self.kinds[self.i] == "name" and self.toks[self.i].text in self.typedefs
        )

    # ------------------------------------------------------------ recovery

    def _skip_braces(self) -> None:
        """Skip a balanced '{ ... }' starting at the current '{'."""
        depth = 0
        keys = self.keys
        while keys[self.i] != "":
            k = keys[self.i]
            self.i += 1
            if k == "{":
                depth += 1
            elif k == "}":
                depth -= 1
                if depth == 0:
                    return

    def _sync_statement(self) -> None:
        """Skip to the end of the broken statement: after ';', before '}', or over a block."""
        keys = self.keys
        parens = 0
        while True:
            k = keys[self.i]
            if k == "" or k == "}":
                return
            if k == "{":
                self._skip_braces()
                return
            if k == ";":
                nxt = self.toks[self.i + 1] if self.i + 1 < len(self.toks) else None
                self.i += 1
                if parens <= 0 or nxt is None or nxt.pos.line != self.toks[self.i - 1].pos.line:
                    return
                continue
            if k == "(":
                parens += 1
            elif k == ")":
                parens -= 1
            self.i += 1

    def _sync_top(self) -> None:
        """Skip to the next file-scope declaration."""
        keys = self.keys
        while True:
            k = keys[self.i]
            if k == "":
                return
            if k == ";" or k == "}":
                self.i += 1
                return
            if k == "{":
                self._skip_braces()
                if keys[self.i] == ";":
                    self.i += 1
                return
            self.i += 1

    # ------------------------------------------------------------ file scope

    # BNF: translation_unit = { external_declaration } EOF
    def _parse_translation_unit(self) -> None:
        spans = self.function_spans
        while self.keys[self.i] != "":
            start = self.i
            if spans is not None:
                count, state = (
                    len(self.items),
                    check_memo.parser_state(self.typedefs, self.enumerators),
                )
            try:
                self._parse_external_declaration()
            except _Fail:
                self.new_structs.clear()
                self._sync_top()
            self.depth = 0
            if self.i == start:
                self.i += 1
            elif spans is not None and len(self.items) > count:
                last = self.items[-1]
                if type(last) is n.FuncDef and last.body is not None:
                    spans.append((last, start, self.i, state))

    # BNF: external_declaration = ";" | typedef_declaration
    # BNF:     | [ "_AUTORUN_" ] declaration_specifiers ( ";" | function_definition | init_declarator { "," init_declarator } ";" )
    def _parse_external_declaration(self) -> None:
        k = self.keys[self.i]
        if k == ";":
            self.i += 1
            return
        if k == "typedef":
            self.items.append(self._parse_typedef_declaration())
            return
        autorun = None
        if k == "_AUTORUN_":
            autorun = self._advance()
        if not self._starts_declaration():
            raise self._unknown_start(file_scope=True)
        spec, storage = self._parse_declaration_specifiers("file")
        self._flush_structs()
        if self._accept(";"):
            if autorun is not None:
                self._error(autorun.pos, "_AUTORUN_ must be followed by a function definition")
            elif spec.struct_def is None and self.keys[self.i - 2] != "}":  # not `enum {...};`
                self.sink.warning(spec.pos, "declaration does not declare anything")
            return
        decls: list[n.VarDecl] = []
        first = True
        while True:
            pointers, name_tok, dims = self._parse_declarator()
            if self.keys[self.i] == "(":
                assert name_tok is not None
                if first:
                    fd = self._parse_function_definition(spec, pointers, name_tok, autorun, True)
                    self.items.append(fd)
                    if fd.body is not None or not self._accept(","):
                        if fd.body is None:
                            self._expect(";", "after function declaration")
                        return
                else:  # `int f(int), g(int), a;`: one more prototype
                    params = self._parse_parameter_list()
                    ret = _with_pointers(spec, pointers)
                    self.items.append(
                        n.FuncDef(name_tok.pos, ret, name_tok.text, params, None, False)
                    )
                    if not self._accept(","):
                        break
                first = False
                continue
            if autorun is not None:
                self._error(autorun.pos, "_AUTORUN_ must be followed by a function definition")
                autorun = None
            decls.append(self._finish_var_decl(spec, pointers, name_tok, dims))
            first = False
            if not self._accept(","):
                break
        self._expect(";", "after declaration")
        if storage != "extern":
            self.items.extend(decls)

    def _flush_structs(self) -> None:
        self.items.extend(self.new_structs)
        self.new_structs.clear()

    def _unknown_start(self, file_scope: bool) -> _Fail:
        """Tailored message for a declaration or statement that starts wrongly."""
        t = self._tok()
        nxt = self._peek_key()
        if t.kind == "name" and (
            self._peek_kind() == "name"
            or (nxt == "*" and self._peek_kind(2) == "name" and file_scope)
        ):
            known = [*sorted(BASIC_WORDS | INTN_TYPES), *sorted(self.typedefs)]
            return self._fail_here(f"unknown type name '{t.text}'" + did_you_mean(t.text, known))
        if file_scope and t.kind == "name" and nxt == "(":
            return self._fail_here(
                f"missing return type of function '{t.text}' (write e.g. 'void {t.text}(...)')"
            )
        if file_scope:
            return self._fail_here(
                f"expected a declaration or function definition before {_describe(t)}"
            )
        return self._fail_here(f"expected statement before {_describe(t)}")

    # BNF: function_definition = parameter_list ( compound_statement | ";" )
    def _parse_function_definition(
        self,
        spec: n.TypeRef,
        pointers: int,
        name_tok: Token,
        autorun: Token | None,
        more: bool = False,
    ) -> n.FuncDef:
        params = self._parse_parameter_list()
        ret = _with_pointers(spec, pointers)
        if self.keys[self.i] == "{":
            mark, hidden = len(self.block_typedefs), len(self.hidden_typedefs)
            for p in params:  # a parameter's name hides a typedef name in the body
                self._hide_typedef(p.name)
            try:
                body = self._parse_compound_statement()
            finally:
                self._end_scope(mark, hidden)
            return n.FuncDef(name_tok.pos, ret, name_tok.text, params, body, autorun is not None)
        if not more:  # else the caller reads `,` (more declarators) or `;`
            self._expect(";", "after function declaration")
        if autorun is not None:
            self._error(autorun.pos, "_AUTORUN_ must be followed by a function definition")
        return n.FuncDef(name_tok.pos, ret, name_tok.text, params, None, False)

    # BNF: parameter_list = "(" [ "void" | parameter_declaration { "," parameter_declaration } ] ")"
    def _parse_parameter_list(self) -> tuple[n.Param, ...]:
        self._expect("(")
        if self._accept(")"):
            return ()
        if self.keys[self.i] == "void" and self._peek_key() == ")":
            self.i += 2
            return ()
        params: list[n.Param] = []
        while True:
            params.append(self._parse_parameter_declaration())
            if not self._accept(","):
                break
        self._expect(")", "after parameters" if self.keys[self.i] == "" else "")
        return tuple(params)

    # BNF: parameter_declaration = declaration_specifiers { "*" [ "const" ] } [ NAME ] { "[" [ conditional_expression ] "]" }
    def _parse_parameter_declaration(self) -> n.Param:
        t = self._tok()
        if self.keys[self.i] == "...":
            raise self._fail_here("variadic functions ('...') are not supported in HMPL")
        if not self._is_type_start(self.i) and self.keys[self.i] not in STORAGE:
            if t.kind == "name" and self._peek_kind() == "name":
                raise self._unknown_start(file_scope=False)
            raise self._fail_here(f"expected parameter type before {_describe(t)}")
        spec, _ = self._parse_declaration_specifiers("param")
        pointers, name_tok, dims = self._parse_declarator(abstract=True)
        if name_tok is not None:
            self._not_an_enumerator(name_tok)
        name = name_tok.text if name_tok is not None else ""
        pos = name_tok.pos if name_tok is not None else t.pos
        return n.Param(pos, _with_pointers(spec, pointers), name, dims)

    def _block_typedef(self) -> n.DeclStmt:
        """A typedef inside a function: its names are types until the block ends."""
        kw = self._tok()
        items = self.items
        self.items = []  # the extra declarators go here, not to file scope
        try:
            last = self._parse_typedef_declaration(block=True)
            tds = (*self.items, last)
        finally:
            self.items = items
        return n.DeclStmt(kw.pos, tds)  # type: ignore[arg-type]

    # BNF: typedef_declaration = "typedef" declaration_specifiers declarator { "," declarator } ";"
    def _parse_typedef_declaration(self, block: bool = False) -> n.Typedef:
        kw = self._advance()
        spec, _ = self._parse_declaration_specifiers("block" if block else "file")
        if block:
            self.new_structs.clear()
        else:
            self._flush_structs()
        result = None
        while True:
            pointers, name_tok, dims = self._parse_declarator()
            assert name_tok is not None
            if name_tok.text in PREDEFINED_TYPES:
                self._error(name_tok.pos, f"'{name_tok.text}' is a built-in type of HMPL")
            td = n.Typedef(kw.pos, name_tok.text, _with_pointers(spec, pointers), dims)
            if block and name_tok.text not in self.typedefs:
                self.block_typedefs.append(name_tok.text)
            self.typedefs.add(name_tok.text)
            if result is None:
                result = td
            else:
                self.items.append(result)
                result = td
            if not self._accept(","):
                break
        self._expect(";", "after typedef")
        return result

    # ------------------------------------------------------------ types and declarators

    # BNF: declaration_specifiers = { "const" | "volatile" | "static" | "extern" | type_specifier }+
    # BNF: type_specifier = "void" | "char" | "short" | "int" | "long" | "float" | "double"
    # BNF:     | "signed" | "unsigned" | INTN_T | struct_or_union_specifier | enum_specifier
    # BNF:     | TYPEDEF_NAME
    def _parse_declaration_specifiers(self, scope: str) -> tuple[n.TypeRef, str | None]:
        start = self._tok()
        keys = self.keys
        k = keys[self.i]
        if k in BASIC_WORDS and keys[self.i + 1] not in DECL_START:
            base = CANONICAL.get((k,))  # the common case: one word (`int`, `double`, ...)
            if base is not None:
                self.i += 1
                return n.TypeRef(start.pos, base, 0, False, None), None
        words: list[str] = []
        named: str | None = None
        struct_def: n.StructDef | None = None
        is_const = False
        storage: str | None = None
        while True:
            k = keys[self.i]
            if k in BASIC_WORDS:
                words.append(k)
                self.i += 1
            elif k in QUALIFIERS:
                is_const = is_const or k == "const"
                self.i += 1
            elif k in STORAGE:
                t = self._advance()
                if scope in ("param", "field", "type") and k == "static":
                    self._error(t.pos, "'static' is not allowed here")
                elif scope in ("param", "block", "field", "type") and k == "extern":
                    self._error(t.pos, "'extern' is not allowed here")
                storage = k
            elif k in INTN_TYPES or (
                self.kinds[self.i] == "name"
                and named is None
                and not words
                and self.toks[self.i].text in self.typedefs
            ):
                if named is not None or words:
                    raise self._fail_here(
                        f"invalid combination of type specifiers before {_describe(self._tok())}"
                    )
                named = self.toks[self.i].text
                self.i += 1
            elif k in ("struct", "union"):
                if named is not None or words:
                    raise self._fail_here("invalid combination of type specifiers")
                named, struct_def = self._parse_struct_or_union_specifier(scope)
            elif k == "enum":
                if named is not None or words:
                    raise self._fail_here("invalid combination of type specifiers")
                self._parse_enum_specifier()
                named = "int32_t"
            else:
                break
        if named is None:
            if not words:
                raise self._fail_here(f"expected a type before {_describe(self._tok())}")
            base = CANONICAL.get(tuple(sorted(words)))
            if base is None:
                self._error(start.pos, f"invalid type '{' '.join(words)}'")
                base = "int32_t"
        else:
            base = named
        return n.TypeRef(start.pos, base, 0, is_const, struct_def), storage

    # BNF: struct_or_union_specifier = ( "struct" | "union" ) ( NAME [ "{" struct_declaration_list "}" ] | "{" struct_declaration_list "}" )
    def _parse_struct_or_union_specifier(self, scope: str) -> tuple[str, n.StructDef | None]:
        kw = self._advance()
        tag = ""
        if self.kinds[self.i] == "name" or self.keys[self.i] in INTN_TYPES:
            tag = self._advance().text
        if self.keys[self.i] != "{":
            if not tag:
                raise self._fail_here(f"expected a tag name or '{{' after '{kw.text}'")
            return f"{kw.text} {tag}", None
        if scope not in ("file", "field", "block"):
            self._error(kw.pos, f"{kw.text} definitions are only allowed in declarations in HMPL")
        fields = self._parse_struct_declaration_list()
        sd = n.StructDef(kw.pos, kw.text, tag, fields)
        if tag:
            self.new_structs.append(sd)
            return f"{kw.text} {tag}", sd
        return kw.text, sd

    # BNF: struct_declaration_list = "{" { struct_declaration } "}"
    def _parse_struct_declaration_list(self) -> tuple[n.VarDecl, ...]:
        lbrace = self._expect("{")
        fields: list[n.VarDecl] = []
        names: set[str] = set()
        while self.keys[self.i] not in ("}", ""):
            start = self.i
            try:
                self._parse_struct_declaration(fields, names)
            except _Fail:
                self._sync_statement()
                if self.i == start:
                    self.i += 1
        if self.keys[self.i] != "}":
            self._error(self._tok().pos, "expected '}' at end of input")
            self.sink.note(lbrace.pos, "to match this '{'")
            raise _Fail
        self.i += 1
        if not fields:
            self._error(lbrace.pos, "a struct or union needs at least one member")
        return tuple(fields)

    # BNF: struct_declaration = declaration_specifiers declarator { "," declarator } ";"
    def _parse_struct_declaration(self, fields: list[n.VarDecl], names: set[str]) -> None:
        if not self._is_type_start(self.i):
            if self._tok().kind == "name" and self._peek_kind() == "name":
                raise self._unknown_start(file_scope=False)
            raise self._fail_here(f"expected a member declaration before {_describe(self._tok())}")
        spec, _ = self._parse_declaration_specifiers("field")
        while True:
            pointers, name_tok, dims = self._parse_declarator()
            assert name_tok is not None
            if self.keys[self.i] == ":":
                raise self._fail_here("bit-fields are not supported in HMPL")
            if self.keys[self.i] == "=":
                raise self._fail_here("struct members cannot have initializers")
            if name_tok.text in names:
                self._error(name_tok.pos, f"duplicate member '{name_tok.text}'")
            names.add(name_tok.text)
            fields.append(
                n.VarDecl(name_tok.pos, _with_pointers(spec, pointers), name_tok.text, dims)
            )
            if not self._accept(","):
                break
        self._expect(";", "after struct member")

    # BNF: enum_specifier = "enum" ( NAME [ "{" enumerator_list "}" ] | "{" enumerator_list "}" )
    # BNF: enumerator_list = enumerator { "," enumerator } [ "," ]
    # BNF: enumerator = NAME [ "=" conditional_expression ]
    def _parse_enum_specifier(self) -> None:
        self.i += 1
        tag = self._advance().text if self.kinds[self.i] == "name" else ""
        if self.keys[self.i] != "{":
            if not tag:
                raise self._fail_here("expected a tag name or '{' after 'enum'")
            return
        self.i += 1
        value = 0
        while self.keys[self.i] != "}":
            if self.kinds[self.i] != "name":
                raise self._fail_here(
                    f"expected an enumerator name before {_describe(self._tok())}"
                )
            name = self._advance()
            self._not_an_enumerator(name)
            reported = False
            if self._accept("="):
                e = self._parse_conditional_expression()
                try:
                    folded = _fold(e)
                except _FoldError as exc:
                    self._error(exc.pos, f"{exc} in the value of enumerator '{name.text}'")
                    folded, reported = 0, True
                if folded is None:
                    self._error(
                        e.pos, f"the value of enumerator '{name.text}' is not an integer constant"
                    )
                    folded, reported = 0, True
                value = folded
            if not reported and not INT32_MIN <= value <= INT32_MAX:
                self._error(
                    name.pos,
                    f"enumerator value {value} of '{name.text}' is outside "
                    f"the range of int [{INT32_MIN}, {INT32_MAX}]",
                )
                value = 0  # one error, not one per following enumerator
            self.enumerators[name.text] = value
            value += 1
            if not self._accept(","):
                break
        self._expect("}", f"at end of enum{' ' + tag if tag else ''}")

    def _not_an_enumerator(self, name: Token) -> None:
        if name.text in self.enumerators:
            self._error(name.pos, f"'{name.text}' is already an enumerator")

    # BNF: declarator = { "*" { "const" | "volatile" } } NAME { "[" [ conditional_expression ] "]" }
    def _parse_declarator(
        self, abstract: bool = False
    ) -> tuple[int, Token | None, tuple[n.Expr | None, ...]]:
        keys = self.keys
        pointers = 0
        while keys[self.i] == "*":
            self.i += 1
            pointers += 1
            while keys[self.i] in QUALIFIERS:
                self.i += 1
        name_tok: Token | None = None
        if self.kinds[self.i] == "name":
            name_tok = self._advance()
        elif keys[self.i] == "(":
            raise self._fail_here(
                "function pointers and parenthesised declarators are not supported in HMPL"
            )
        elif not abstract:
            t = self._tok()
            if t.kind == "keyword":
                raise self._fail_here(f"'{t.text}' is a keyword and cannot be used as a name")
            raise self._fail_here(f"expected a name before {_describe(t)}")
        dims: list[n.Expr | None] = []
        while keys[self.i] == "[":
            self.i += 1
            if self._accept("]"):
                dims.append(None)
                continue
            dims.append(self._parse_conditional_expression())
            self._expect("]", "after array size")
        return pointers, name_tok, tuple(dims)

    # BNF: type_name = declaration_specifiers { "*" [ "const" ] } { "[" conditional_expression "]" }
    # BNF:     (a compound literal's type_name may leave its first size out: "(int[]){1, 2}")
    def _parse_type_name(self, open_array: bool = False) -> tuple[n.TypeRef, tuple]:
        """The type and its dimensions; with `open_array` the dimensions may hold None
        (`int[]`, for a compound literal: the caller checks them)."""
        spec, _ = self._parse_declaration_specifiers("type")
        pointers, name_tok, dims = self._parse_declarator(abstract=True)
        if name_tok is not None:
            self._error(name_tok.pos, f"unexpected name '{name_tok.text}' in a type name")
        if open_array:
            return _with_pointers(spec, pointers), dims
        if any(d is None for d in dims):
            self._error(spec.pos, "array size missing in a type name")
        return _with_pointers(spec, pointers), tuple(d for d in dims if d is not None)

    def _finish_var_decl(
        self,
        spec: n.TypeRef,
        pointers: int,
        name_tok: Token | None,
        dims: tuple[n.Expr | None, ...],
        is_static: bool = False,
    ) -> n.VarDecl:
        assert name_tok is not None
        self._not_an_enumerator(name_tok)
        init = None
        if self._accept("="):
            init = self._parse_initializer()
        if spec.base == "void" and pointers == 0:
            self._error(name_tok.pos, f"variable '{name_tok.text}' declared void")
        return n.VarDecl(
            name_tok.pos,
            _with_pointers(spec, pointers),
            name_tok.text,
            _infer_first_dim(dims, init, pointers > 0 or spec.base in SCALAR_BASES),
            init,
            is_static,
        )

    # BNF: initializer = assignment_expression
    # BNF:     | "{" [ initializer_item { "," initializer_item } [ "," ] ] "}"
    def _parse_initializer(self) -> n.Expr | n.InitList:
        if self.keys[self.i] != "{":
            return self._parse_assignment_expression()
        lbrace = self._advance()
        self._enter()
        items: list[n.Expr | n.InitList | n.Designated] = []
        while self.keys[self.i] != "}":
            if self.keys[self.i] in (".", "["):
                items.append(self._parse_designated_initializer())
            else:
                items.append(self._parse_initializer())
            if not self._accept(","):
                break
        self._expect("}", "at end of initializer list" if self.keys[self.i] == "" else "")
        self.depth -= 1
        return n.InitList(lbrace.pos, tuple(items))

    # BNF: initializer_item = [ ( "." NAME | "[" conditional_expression "]" ) "=" ] initializer
    def _parse_designated_initializer(self) -> n.Designated:
        t = self._advance()
        field: str | None = None
        index: n.Expr | None = None
        if t.text == ".":
            if self.kinds[self.i] != "name":
                raise self._fail_here(
                    f"expected a member name after '.' before {_describe(self._tok())}"
                )
            field = self._advance().text
        else:
            index = self._parse_conditional_expression()
            self._expect("]", "after designator index")
        if self.keys[self.i] in (".", "["):
            raise self._fail_here(
                "nested designators ('.a.b =', '[i][j] =') are not supported in HMPL; "
                "use nested braces"
            )
        self._expect("=", "after designator")
        return n.Designated(t.pos, field, index, self._parse_initializer())

    # ------------------------------------------------------------ statements

    # BNF: compound_statement = "{" { block_item } "}"
    def _parse_compound_statement(self) -> n.Block:
        lbrace = self._expect("{")
        mark, hidden = len(self.block_typedefs), len(self.hidden_typedefs)
        try:
            return self._compound_items(lbrace)
        finally:
            self._end_scope(mark, hidden)

    def _end_scope(self, mark: int, hidden: int) -> None:
        """A block ends: its typedef names end with it, those its names hid are back."""
        for name in self.block_typedefs[mark:]:
            self.typedefs.discard(name)
        del self.block_typedefs[mark:]
        self.typedefs.update(self.hidden_typedefs[hidden:])
        del self.hidden_typedefs[hidden:]

    def _hide_typedef(self, name: str) -> None:
        """An ordinary identifier declared in a block hides a typedef name of the same
        spelling until the block ends (C 6.2.1: `struct s s;` makes `s` a variable)."""
        if name in self.typedefs:
            self.typedefs.discard(name)
            self.hidden_typedefs.append(name)

    def _compound_items(self, lbrace: Token) -> n.Block:
        self._enter()
        items: list[n.Stmt] = []
        keys = self.keys
        depth = self.depth
        while keys[self.i] != "}" and keys[self.i] != "":
            start = self.i
            try:
                items.append(self._parse_block_item())
            except _Fail:
                self.depth = depth
                self._sync_statement()
                if self.i == start:
                    self.i += 1
        if keys[self.i] != "}":
            self._error(self._tok().pos, "expected '}' at end of input")
            self.sink.note(lbrace.pos, "to match this '{'")
        else:
            self.i += 1
        self.depth -= 1
        return n.Block(lbrace.pos, tuple(items))

    # BNF: block_item = declaration | statement
    def _parse_block_item(self) -> n.Stmt:
        if self._starts_declaration() and not (
            self.kinds[self.i] == "name" and self._peek_key() == ":"
        ):  # `T:` with T a typedef name is a label (labels have their own name space)
            return self._parse_declaration()
        return self._parse_statement()

    # BNF: declaration = typedef_declaration
    # BNF:     | declaration_specifiers [ init_declarator { "," init_declarator } ] ";"
    # BNF: init_declarator = declarator [ "=" initializer ]
    def _parse_declaration(self) -> n.DeclStmt:
        start = self._tok()
        if self.keys[self.i] == "typedef":
            return self._block_typedef()
        spec, storage = self._parse_declaration_specifiers("block")
        self.new_structs.clear()  # defined where the declaration is lowered, in its block
        decls: list[n.VarDecl] = []
        if self.keys[self.i] == ";" and spec.struct_def is not None:
            decls.append(n.VarDecl(start.pos, spec, ""))  # `struct S { ... };` alone
        if self.keys[self.i] != ";":
            while True:
                pointers, name_tok, dims = self._parse_declarator()
                if name_tok is not None:
                    self._hide_typedef(name_tok.text)
                if self.keys[self.i] == "(":  # a prototype: checked against the definition
                    assert name_tok is not None
                    params = self._parse_parameter_list()
                    ret = _with_pointers(spec, pointers)
                    proto = n.FuncDef(name_tok.pos, ret, name_tok.text, params, None, False, True)
                    self.items.append(proto)  # checked with the file's declarations
                    decls.append(proto)  # type: ignore[arg-type]  # and visible in its block
                    if not self._accept(","):
                        break
                    continue
                decls.append(
                    self._finish_var_decl(
                        spec, pointers, name_tok, dims, is_static=storage == "static"
                    )
                )
                if not self._accept(","):
                    break
        self._expect(";", "after declaration")
        return n.DeclStmt(start.pos, tuple(decls))

    # BNF: statement = compound_statement | if_statement | while_statement | do_statement
    # BNF:     | for_statement | switch_statement | case_label | default_label | label
    # BNF:     | jump_statement | ";" | expression ";" | till_with_body | till_statement
    def _parse_statement(self) -> n.Stmt:
        k = self.keys[self.i]
        method = self._STATEMENTS.get(k)
        if method is not None:
            self._enter()
            try:
                return method(self)
            finally:
                self.depth -= 1
        t = self._tok()
        if k == ";":
            self.i += 1
            return n.Empty(t.pos)
        if self.kinds[self.i] == "name":
            nxt = self._peek_key()
            if self._peek_kind() == "name":
                raise self._unknown_start(file_scope=False)
            if nxt == ":":
                return self._parse_label()
        elif k == "else":
            raise self._fail_here("'else' without a previous 'if'")
        elif k == "":
            raise self._fail_here("expected statement before end of file")
        expr = self._parse_expression()
        if (
            self.keys[self.i] == "{"
            and isinstance(expr, n.Call)
            and isinstance(expr.func, n.Name)
            and expr.func.id == "Till"
            and len(expr.args) == 1
        ):
            return self._parse_till_body(expr)
        if self.keys[self.i] != ";" and self._is_till_at_line_end(expr):
            # The manual prints `Till(cond)` without its ';' (19.2, 6.1.2): accept it.
            prev = self.toks[self.i - 1]
            self.sink.warning(_end_of(prev), "expected ';' after Till(...); one is assumed")
            return n.ExprStmt(t.pos, expr)
        self._expect(";", "after expression")
        return n.ExprStmt(t.pos, expr)

    def _is_till_at_line_end(self, expr: n.Expr) -> bool:
        """True if `expr` is a call `Till(cond)` and the next token is on a later line."""
        return (
            isinstance(expr, n.Call)
            and isinstance(expr.func, n.Name)
            and expr.func.id == "Till"
            and self.toks[self.i].pos.line != self.toks[self.i - 1].pos.line
        )

    # BNF: till_with_body = "Till" "(" expression ")" compound_statement [ ";" ]
    # BNF: till_statement = "Till" "(" expression ")" ( ";" | end of line: a warning )
    def _parse_till_body(self, till: n.Call) -> n.While:
        """`Till(cond) { body };` (manual 20.1.2): run the body each pass until cond holds,
        the same as `while (!(cond)) { body }`."""
        body = self._parse_compound_statement()
        self._accept(";")
        cond = till.args[0]
        return n.While(till.pos, n.Unary(cond.pos, "!", cond), body)

    # BNF: if_statement = "if" "(" expression ")" statement [ "else" statement ]
    def _parse_if_statement(self) -> n.If:
        kw = self._advance()
        cond = self._condition("if")
        then = self._parse_statement()
        else_ = self._parse_statement() if self._accept("else") else None
        return n.If(kw.pos, cond, then, else_)

    def _condition(self, keyword: str) -> n.Expr:
        """'(' expression ')' after if/while/switch; a broken condition is skipped."""
        if self.keys[self.i] != "(":
            raise self._fail_here(f"expected '(' after '{keyword}'")
        lparen = self._advance()
        try:
            e = self._parse_expression()
            self._expect(")")
        except _Fail:
            self._skip_to_close_paren(in_for=False)
            return n.IntLit(lparen.pos, 0)  # stands in for the broken condition
        return e

    def _skip_to_close_paren(self, in_for: bool) -> None:
        """After an error inside '( ... )': skip past the closing ')' so that the
        statement body still parses; stop before a '{' or '}' (the ')' is missing)."""
        keys = self.keys
        depth = 0
        while True:
            k = keys[self.i]
            if k == "" or k == "{" or k == "}" or (k == ";" and not in_for):
                return
            self.i += 1
            if k == "(":
                depth += 1
            elif k == ")":
                if depth == 0:
                    return
                depth -= 1

    # BNF: while_statement = "while" "(" expression ")" statement
    def _parse_while_statement(self) -> n.While:
        kw = self._advance()
        cond = self._condition("while")
        return n.While(kw.pos, cond, self._parse_statement())

    # BNF: do_statement = "do" statement "while" "(" expression ")" ";"
    def _parse_do_statement(self) -> n.DoWhile:
        kw = self._advance()
        body = self._parse_statement()
        if self.keys[self.i] != "while":
            raise self._fail_here(
                f"expected 'while' after 'do' body before {_describe(self._tok())}"
            )
        self.i += 1
        cond = self._condition("while")
        self._expect(";", "after do/while statement")
        return n.DoWhile(kw.pos, body, cond)

    # BNF: for_statement = "for" "(" ( declaration | [ expression ] ";" ) [ expression ] ";" [ expression ] ")" statement
    def _parse_for_statement(self) -> n.For:
        mark, hidden = len(self.block_typedefs), len(self.hidden_typedefs)
        try:  # the names the first clause declares end with the loop
            return self._for_statement_rest()
        finally:
            self._end_scope(mark, hidden)

    def _for_statement_rest(self) -> n.For:
        kw = self._advance()
        if self.keys[self.i] != "(":
            raise self._fail_here("expected '(' after 'for'")
        self.i += 1
        init: n.DeclStmt | n.ExprStmt | None = None
        cond = step = None
        try:
            if self._starts_declaration():
                if self.keys[self.i] == "typedef":
                    raise self._fail_here("a for loop's first clause declares variables only")
                init = self._parse_declaration()
                proto = next((d for d in init.decls if isinstance(d, n.FuncDef)), None)
                if proto is not None:
                    self._error(proto.pos, "a for loop's first clause declares variables only")
                    init = None
            elif not self._accept(";"):
                t = self._tok()
                init = n.ExprStmt(t.pos, self._parse_expression())
                self._expect(";", "in 'for' statement")
            cond = None if self.keys[self.i] == ";" else self._parse_expression()
            self._expect(";", "in 'for' statement")
            step = None if self.keys[self.i] == ")" else self._parse_expression()
            self._expect(")")
        except _Fail:
            self._skip_to_close_paren(in_for=True)
        return n.For(kw.pos, init, cond, step, self._parse_statement())

    # BNF: switch_statement = "switch" "(" expression ")" statement
    def _parse_switch_statement(self) -> n.Switch:
        kw = self._advance()
        expr = self._condition("switch")
        body = self._parse_statement()
        if isinstance(body, (n.Case, n.Default)):
            # `switch (x) case 1: stmt` — a label stands before a statement, so the body
            # is the labels and the statement after them (a block of its own, as with braces)
            items = [body]
            while isinstance(items[-1], (n.Case, n.Default)):
                items.append(self._parse_statement())
            body = n.Block(body.pos, tuple(items))
        return n.Switch(kw.pos, expr, body)

    # BNF: case_label = "case" conditional_expression ":"
    def _parse_case_label(self) -> n.Case:
        kw = self._advance()
        value = self._parse_conditional_expression()
        if self.keys[self.i] != ":":
            raise self._fail_here(
                f"expected ':' after 'case' value before {_describe(self._tok())}"
            )
        self.i += 1
        return n.Case(kw.pos, value)

    # BNF: default_label = "default" ":"
    def _parse_default_label(self) -> n.Default:
        kw = self._advance()
        self._expect(":", "after 'default'")
        return n.Default(kw.pos)

    # BNF: label = NAME ":"
    def _parse_label(self) -> n.Label:
        name = self._advance()
        self.i += 1
        return n.Label(name.pos, name.text)

    # BNF: jump_statement = "break" ";" | "continue" ";" | "return" [ expression ] ";" | "goto" NAME ";"
    def _parse_jump_statement(self) -> n.Stmt:
        kw = self._advance()
        if kw.text == "goto":
            if self.kinds[self.i] != "name":
                raise self._fail_here(
                    f"expected a label name after 'goto' before {_describe(self._tok())}"
                )
            label = self._advance()
            self._expect(";", "after 'goto' statement")
            return n.Goto(kw.pos, label.text)
        if kw.text == "return":
            value = None if self.keys[self.i] == ";" else self._parse_expression()
            self._expect(";", "after return statement")
            return n.Return(kw.pos, value)
        self._expect(";", f"after '{kw.text}'")
        return n.Break(kw.pos) if kw.text == "break" else n.Continue(kw.pos)

    _STATEMENTS: ClassVar[dict[str, Callable[[Parser], n.Stmt]]] = {
        "{": _parse_compound_statement,
        "if": _parse_if_statement,
        "while": _parse_while_statement,
        "do": _parse_do_statement,
        "for": _parse_for_statement,
        "switch": _parse_switch_statement,
        "case": _parse_case_label,
        "default": _parse_default_label,
        "break": _parse_jump_statement,
        "continue": _parse_jump_statement,
        "return": _parse_jump_statement,
        "goto": _parse_jump_statement,
    }

    # ------------------------------------------------------------ expressions

    # BNF: expression = assignment_expression { "," assignment_expression }
    def _parse_expression(self) -> n.Expr:
        start = self._tok()
        e = self._parse_assignment_expression()
        if self.keys[self.i] != ",":
            return e
        items = [e]
        while self._accept(","):
            items.append(self._parse_assignment_expression())
        return n.Comma(start.pos, tuple(items))

    # BNF: assignment_expression = conditional_expression [ ASSIGN_OP assignment_expression ]
    # BNF: ASSIGN_OP = "=" | "+=" | "-=" | "*=" | "/=" | "%=" | "<<=" | ">>=" | "&=" | "|=" | "^="
    def _parse_assignment_expression(self) -> n.Expr:
        left = self._parse_conditional_expression()
        k = self.keys[self.i]
        if k in ASSIGN_OPS:
            op = self.toks[self.i]
            self.i += 1
            return n.Assign(op.pos, k, left, self._parse_assignment_expression())
        return left

    # BNF: conditional_expression = binary_expression [ "?" expression ":" conditional_expression ]
    def _parse_conditional_expression(self) -> n.Expr:
        c = self._parse_binary_expression(1)
        if self.keys[self.i] != "?":
            return c
        q = self._advance()
        then = self._parse_expression()
        if self.keys[self.i] != ":":
            raise self._fail_here(
                f"expected ':' in conditional expression before {_describe(self._tok())}"
            )
        self.i += 1
        return n.Cond(q.pos, c, then, self._parse_conditional_expression())

    # BNF: binary_expression = cast_expression { BINARY_OP cast_expression }
    # BNF:     (C precedence, all left-associative, loosest first: || ; && ; | ; ^ ; & ;
    # BNF:      == != ; < > <= >= ; << >> ; + - ; * / %)
    def _parse_binary_expression(self, min_prec: int) -> n.Expr:
        keys = self.keys
        i = self.i
        kind = self.kinds[i]
        if kind == "name" and keys[i + 1] not in POSTFIX_START and keys[i] not in self.enumerators:
            # the common operand, a plain name: skip the cast/unary/postfix/primary chain
            t = self.toks[i]
            left: n.Expr = n.Name(t.pos, t.text)
            self.i = i + 1
        elif kind == "int" and keys[i + 1] not in POSTFIX_START:
            t = self.toks[i]
            left = n.IntLit(t.pos, t.value, t.suffix, t.text[0] != "0" or not t.value)  # type: ignore[arg-type]
            self.i = i + 1
        else:
            left = self._parse_cast_expression()
        count = 0
        while True:
            op = keys[self.i]
            prec = BINARY_PREC.get(op)
            if prec is None or prec < min_prec:
                return left
            t = self.toks[self.i]
            count += 1
            if count > MAX_OPERATORS:
                raise self._fail_here(
                    f"more than {MAX_OPERATORS} operators in a row (the limit of HMPL)"
                )
            self.i += 1
            left = n.Binary(t.pos, op, left, self._parse_binary_expression(prec + 1))

    # BNF: cast_expression = "(" type_name ")" cast_expression | compound_literal | unary_expression
    def _parse_cast_expression(self) -> n.Expr:
        if self.keys[self.i] == "(" and self._is_type_start(self.i + 1):
            lp = self._advance()
            ty, dims = self._parse_type_name(open_array=True)
            self._expect(")", "after type name")
            if self.keys[self.i] == "{":
                return self._postfix_operators(self._parse_compound_literal(lp, ty, dims))
            if any(d is None for d in dims):
                self._error(ty.pos, "array size missing in a type name")
            if dims:
                self._error(lp.pos, "cannot cast to an array type")
            return n.Cast(lp.pos, ty, self._parse_cast_expression())
        return self._parse_unary_expression()

    # BNF: compound_literal = "(" type_name ")" "{" [ initializer_item { "," initializer_item } [ "," ] ] "}"
    # BNF:     { "[" expression "]" | "(" [ argument_list ] ")" | "." NAME | "->" NAME | "++" | "--" }
    def _parse_compound_literal(
        self, lp: Token, ty: n.TypeRef, dims: tuple[n.Expr | None, ...]
    ) -> n.CompoundLit:
        init = self._parse_initializer()
        assert isinstance(init, n.InitList)
        if ty.base == "void" and ty.pointers == 0:
            self._error(lp.pos, "a compound literal of type void")
        scalar = ty.pointers > 0 or ty.base in SCALAR_BASES
        return n.CompoundLit(lp.pos, ty, _infer_first_dim(dims, init, scalar), init)

    # BNF: unary_expression = ( "++" | "--" ) unary_expression | ( "-" | "+" | "!" | "~" | "*" | "&" ) cast_expression
    # BNF:     | "sizeof" ( "(" type_name ")" | compound_literal | unary_expression ) | postfix_expression
    def _parse_unary_expression(self) -> n.Expr:
        k = self.keys[self.i]
        if k in UNARY_OPS:
            t = self._advance()
            self._enter()
            e = n.Unary(t.pos, k, self._parse_cast_expression())
            self.depth -= 1
            return e
        if k == "++" or k == "--":
            t = self._advance()
            self._enter()
            e = n.Unary(t.pos, k, self._parse_unary_expression())
            self.depth -= 1
            return e
        if k == "sizeof":
            t = self._advance()
            if self.keys[self.i] == "(" and self._is_type_start(self.i + 1):
                lp = self._advance()
                ty, dims = self._parse_type_name(open_array=True)
                self._expect(")", "after type name")
                if self.keys[self.i] == "{":  # `sizeof (int[]){1, 2}`: of the object
                    lit = self._parse_compound_literal(lp, ty, dims)
                    return n.SizeOf(t.pos, self._postfix_operators(lit))
                if any(d is None for d in dims):
                    self._error(ty.pos, "array size missing in a type name")
                return n.SizeOf(t.pos, ty, tuple(d for d in dims if d is not None))
            self._enter()
            e = n.SizeOf(t.pos, self._parse_unary_expression())
            self.depth -= 1
            return e
        return self._parse_postfix_expression()

    # BNF: postfix_expression = primary_expression { "[" expression "]" | "(" [ argument_list ] ")"
    # BNF:     | "." NAME | "->" NAME | "++" | "--" }
    # BNF: argument_list = assignment_expression { "," assignment_expression }
    def _parse_postfix_expression(self) -> n.Expr:
        return self._postfix_operators(self._parse_primary_expression())

    def _postfix_operators(self, e: n.Expr) -> n.Expr:
        keys = self.keys
        while keys[self.i] in POSTFIX_START:
            t = self.toks[self.i]
            k = keys[self.i]
            self.i += 1
            if k == "(":
                args: list[n.Expr] = []
                if keys[self.i] != ")":
                    while True:
                        args.append(self._parse_assignment_expression())
                        if not self._accept(","):
                            break
                self._expect(")", "" if keys[self.i] != ";" else "before ';' (unclosed call)")
                e = n.Call(e.pos, e, tuple(args))
            elif k == "[":
                idx = self._parse_expression()
                self._expect("]", "after index")
                e = n.Index(t.pos, e, idx)
            elif k == "." or k == "->":
                if self.kinds[self.i] != "name":
                    raise self._fail_here(f"expected a member name after '{k}'")
                name = self._advance()
                e = n.Member(name.pos, e, name.text, k == "->")
            else:
                e = n.Postfix(t.pos, k, e)
        return e

    # BNF: primary_expression = NAME | INT | FLOAT | CHAR | STRING { STRING } | "(" expression ")"
    # BNF:     | compound_literal
    def _parse_primary_expression(self) -> n.Expr:
        t = self.toks[self.i]
        k = t.kind
        if k == "name":
            self.i += 1
            value = self.enumerators.get(t.text)
            if value is not None:
                return n.IntLit(t.pos, value)
            return n.Name(t.pos, t.text)
        if k == "int":
            self.i += 1
            return n.IntLit(t.pos, t.value, t.suffix, t.text[0] != "0" or not t.value)  # type: ignore[arg-type]
        if k == "float":
            self.i += 1
            return n.FloatLit(t.pos, t.value, t.suffix == "f")  # type: ignore[arg-type]
        if k == "char":
            self.i += 1
            return n.CharLit(t.pos, t.value)  # type: ignore[arg-type]
        if k == "string":
            self.i += 1
            if self.kinds[self.i] != "string":
                return n.StrLit(t.pos, t.value)  # type: ignore[arg-type]
            parts = [t.value]
            while self.kinds[self.i] == "string":
                parts.append(self.toks[self.i].value)
                self.i += 1
            return n.StrLit(t.pos, b"".join(parts))  # type: ignore[arg-type]
        if self.keys[self.i] == "(" and self._is_type_start(self.i + 1):
            lp = self._advance()  # after '++', '--' or sizeof: a compound literal (no cast)
            ty, dims = self._parse_type_name(open_array=True)
            self._expect(")", "after type name")
            if self.keys[self.i] != "{":
                raise self._fail_here("expected '{' of a compound literal after the type name")
            return self._parse_compound_literal(lp, ty, dims)
        if self.keys[self.i] == "(":
            self.i += 1
            self._enter()
            e = self._parse_expression()
            self.depth -= 1
            self._expect(")")
            if type(e) is n.Assign and not e.parenthesized:
                e = dataclasses.replace(e, parenthesized=True)  # silences -Wparentheses
            return e
        if k == "keyword" and t.text in TYPE_START:
            raise self._fail_here(f"expected expression before '{t.text}' (a type name here?)")
        raise self._fail_here(f"expected expression before {_describe(t)}")


def _with_pointers(spec: n.TypeRef, pointers: int) -> n.TypeRef:
    if pointers == 0:
        return spec
    return n.TypeRef(spec.pos, spec.base, pointers, spec.is_const, spec.struct_def)


def _infer_first_dim(
    dims: tuple[n.Expr | None, ...], init: n.Expr | n.InitList | None, scalar: bool
) -> tuple[n.Expr | None, ...]:
    """`T a[] = init`: the first dimension from the initializer, as C does, where the
    braces tell it (`scalar`: T is a scalar type); else the checker counts it, with
    brace elision (`struct P ps[] = {1, 2, 3, 4}` has 2 elements)."""
    if not dims or dims[0] is not None or init is None:
        return dims
    count: int | None = None
    if isinstance(init, n.StrLit):
        if len(dims) == 1:
            count = len(init.value) + 1
    elif isinstance(init, n.InitList):
        items = init.items
        if any(isinstance(x, n.Designated) for x in items):
            if len(dims) == 1 and scalar:
                count = _designated_count(items)
        elif len(dims) == 1:
            if len(items) == 1 and isinstance(items[0], n.StrLit):
                count = len(items[0].value) + 1
            elif scalar or all(isinstance(x, n.InitList) for x in items):
                count = len(items)
        elif all(isinstance(x, (n.InitList, n.StrLit)) for x in items):
            count = len(items)
        elif (
            scalar
            and not any(isinstance(x, n.InitList) for x in items)
            and all(isinstance(d, n.IntLit) and d.value > 0 for d in dims[1:])
        ):
            inner = 1
            for d in dims[1:]:
                inner *= d.value  # type: ignore[union-attr]
            count = -(-len(items) // inner)
    if count is None:
        return dims
    return (n.IntLit(init.pos, count), *dims[1:])


def _designated_count(items: tuple) -> int | None:
    """Elements of `T a[] = {..., [k] = v, ...}`: one past the highest index; None when an
    index is no literal (the checker evaluates it) or a member designator is used."""
    count = i = 0
    for x in items:
        if isinstance(x, n.Designated):
            if not isinstance(x.index, n.IntLit):
                return None
            i = x.index.value
        i += 1
        count = max(count, i)
    return count


class _FoldError(Exception):
    """A constant expression that has no value (division by zero, negative shift count)."""

    def __init__(self, pos: SourcePos, message: str) -> None:
        super().__init__(message)
        self.pos = pos


def _fold(e: n.Expr) -> int | None:
    """The exact value of an integer constant expression (enumerator values; the caller
    checks the range), or None if it is not one; _FoldError if it has no value."""
    if isinstance(e, (n.IntLit, n.CharLit)):
        return e.value
    if isinstance(e, n.Cast) and e.type.pointers == 0 and e.type.base not in ("float", "double"):
        return _fold(e.expr)
    if isinstance(e, n.Unary) and e.op in ("-", "+", "~", "!"):
        v = _fold(e.operand)
        if v is None:
            return None
        return {"-": -v, "+": v, "~": ~v, "!": int(not v)}[e.op]
    if isinstance(e, n.Cond):
        c = _fold(e.cond)
        return None if c is None else _fold(e.then if c else e.else_)
    if isinstance(e, n.Binary):
        a, b = _fold(e.left), _fold(e.right)
        if a is None or b is None:
            return None
        op = e.op
        if op in ("/", "%"):
            if b == 0:
                raise _FoldError(e.pos, "division by zero" if op == "/" else "modulo by zero")
            q = abs(a) // abs(b) * (1 if (a < 0) == (b < 0) else -1)
            return q if op == "/" else a - q * b
        if op in ("<<", ">>"):
            if b < 0:
                raise _FoldError(e.pos, f"negative shift count {b}")
            if op == ">>":
                return a >> b
            return a << min(b, 64)  # past 64 bits it is out of every range anyway
        table = {
            "+": lambda: a + b,
            "-": lambda: a - b,
            "*": lambda: a * b,
            "&": lambda: a & b,
            "|": lambda: a | b,
            "^": lambda: a ^ b,
            "==": lambda: int(a == b),
            "!=": lambda: int(a != b),
            "<": lambda: int(a < b),
            ">": lambda: int(a > b),
            "<=": lambda: int(a <= b),
            ">=": lambda: int(a >= b),
            "&&": lambda: int(bool(a and b)),
            "||": lambda: int(bool(a or b)),
        }
        return table[op]() if op in table else None
    return None
