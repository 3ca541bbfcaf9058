"""GDL parser: hand-written recursive descent over the GDL grammar (docs/lang/gdl.md).

Each `_parse_<rule>` carries its rule as a `# BNF:` comment; `docs/lang/gdl.md` is
generated from those lines. Errors are reported to the sink and the parser recovers at
the next `;` (or at a block keyword), so one run reports every syntax error of a file.
The parser knows keywords only by category (object type, state, operator...); whether a
keyword fits the object it is applied to is the checker's business.
"""

from __future__ import annotations

from motionvm.lang.gdl import nodes as n
from motionvm.lang.gdl.lexer import Token
from motionvm.lang.gdl.objects import (
    GLOBAL_ACTIVATORS,
    OPERATOR_WORDS,
    SET_CONSTANTS,
    STATE_WORDS,
    TYPE_BY_NAME,
)
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos
from motionvm.source.suggest import did_you_mean

REL_OPS = ("=", "<>", "<", ">", "<=", ">=")
STRAY_ENDS = {"END$IF": "IF", "ELSE": "IF", "END$WHILE": "WHILE"}
BLOCK_ENDS = frozenset(
    {"END$IF", "ELSE", "END$WHILE", "END$PROCEDURE", "END$MODULE", "PROCEDURE", "MODULE"}
)


MAX_NESTING = 1024
"""Levels of nesting the parser follows: each IF, WHILE, parenthesis and NOT is one
(a documented GDL limit; past it the file is not parsed further)."""
MAX_OPERATORS = 20_000
"""Binary operators in a row (`a + b + ...`, or `*`, AND, OR), at most (a GDL limit)."""


def _article(word: str) -> str:
    return ("an " if word[0] in "aeiou" else "a ") + word


class ParseError(Exception):
    """Abandons the current instruction or declaration; the message is already reported."""


class _TooDeep(Exception):
    """A nest past MAX_NESTING: parsing of the file stops (the error is reported)."""


class Parser:
    """Parses the tokens of one file into a `GdlFile`."""

    def __init__(self, tokens: list[Token], sink: DiagnosticSink) -> None:
        self.toks = tokens
        self.k = 0
        self.sink = sink
        self.depth = 0  # levels of nesting entered (MAX_NESTING)
        # Lines with a lexical error: a parse error there would only repeat it.
        self.bad_lines = {(d.pos.file, d.pos.line) for d in sink.errors()}

    # ------------------------------------------------------------ token helpers

    @property
    def tok(self) -> Token:
        return self.toks[self.k]

    def _advance(self) -> Token:
        t = self.toks[self.k]
        if t.kind != "eof":
            self.k += 1
        return t

    def _is(self, text: str) -> bool:
        t = self.tok
        return t.kind in ("keyword", "delim") and t.text == text

    def _accept(self, text: str) -> Token | None:
        return self._advance() if self._is(text) else None

    def _error(self, pos: SourcePos, message: str) -> None:
        """Report once per position, and not on a line that already has a lexical error."""
        if (pos.file, pos.line) in self.bad_lines:
            return
        if not any(d.pos == pos for d in self.sink.items):
            self.sink.error(pos, message)

    def _fail(self, message: str, tok: Token | None = None) -> ParseError:
        t = tok or self.tok
        self._error(t.pos, message)
        return ParseError(message)

    def _expect(self, text: str, context: str) -> Token:
        if self._is(text):
            return self._advance()
        message = f"expected '{text}' {context}, found {self.tok.describe()}"
        prev = self.toks[self.k - 1] if self.k > 0 else None
        if prev is not None and prev.kind != "string" and prev.pos.line != self.tok.pos.line:
            # Something forgotten at the end of a line: point there, not at the next line.
            end = SourcePos(prev.pos.file, prev.pos.line, prev.pos.col + len(prev.text))
            self._error(end, message)
            raise ParseError(message)
        raise self._fail(message)

    def _enter(self, t: Token) -> None:
        """One more level of nesting at `t`; past MAX_NESTING, one error and the file stops."""
        self.depth += 1
        if self.depth > MAX_NESTING:
            self._error(
                t.pos,
                f"nesting deeper than {MAX_NESTING} levels (the limit of GDL); the rest of the"
                " file is not parsed",
            )
            raise _TooDeep

    def _count(self, count: int, t: Token) -> int:
        """One more operator in a row at `t`; past MAX_OPERATORS, a located error."""
        if count >= MAX_OPERATORS:
            raise self._fail(f"more than {MAX_OPERATORS} operators in a row (the limit of GDL)", t)
        return count + 1

    def _sync(self) -> None:
        """Skip to just after the next ';', or to a block keyword, or to end of file."""
        while self.tok.kind != "eof":
            if self.tok.kind == "keyword" and self.tok.text in BLOCK_ENDS:
                return
            if self._advance().text == ";" and self.toks[self.k - 1].kind == "delim":
                return

    # ------------------------------------------------------------ files and modules

    # BNF: gdl_file = module { module } ;
    def parse_file(self, path: str) -> n.GdlFile:
        modules: list[n.Module] = []
        start = self.tok.pos
        if self.tok.kind == "eof":
            self._error(start, f"empty file: a GDL file holds at least one MODULE ({path})")
        while self.tok.kind != "eof":
            if self._is("MODULE"):
                try:
                    modules.append(self._parse_module())
                except _TooDeep:
                    break
            else:
                self._error(self.tok.pos, f"expected 'MODULE', found {self.tok.describe()}")
                self._advance()
                while self.tok.kind != "eof" and not self._is("MODULE"):
                    self._advance()
        return n.GdlFile(start, tuple(modules))

    # BNF: module = "MODULE" module_name ";" { declaration } { procedure } "END$MODULE" ";" ;
    def _parse_module(self) -> n.Module:
        pos = self._advance().pos
        uses: list[n.UseDecl] = []
        objects: list[n.ObjectDecl] = []
        procs: list[n.Procedure] = []
        name = n.Name(self.tok.pos, "?")
        try:
            name = self._parse_name("module")
            self._expect(";", "after the module name")
        except ParseError:
            self._sync()
        while not self._is("END$MODULE"):
            t = self.tok
            if t.kind == "eof" or self._is("MODULE"):
                self._error(t.pos, f"module '{name.text}' has no END$MODULE before {t.describe()}")
                return n.Module(pos, name, tuple(uses), tuple(objects), tuple(procs))
            try:
                if self._is("PROCEDURE"):
                    procs.append(self._parse_procedure())
                elif procs and (self._is("USE") or t.text in TYPE_BY_NAME):
                    raise self._fail("declarations must come before the procedures of a module")
                elif self._is("USE"):
                    uses.append(self._parse_external_decl())
                else:
                    objects.append(self._parse_object_decl())
            except ParseError:
                before = self.k
                self._sync()
                if self.k == before and self.tok.kind != "eof":
                    self._advance()
                if self._is("END$PROCEDURE"):
                    self._advance()
                    self._accept(";")
        self._advance()
        try:
            self._expect(";", "after END$MODULE")
        except ParseError:
            pass
        return n.Module(pos, name, tuple(uses), tuple(objects), tuple(procs))

    def _parse_name(self, what: str) -> n.Name:
        t = self.tok
        if t.kind == "ident":
            self._advance()
            return n.Name(t.pos, t.text)
        if t.kind == "keyword":
            self._advance()
            self._error(
                t.pos, f"'{t.text}' is a reserved word and cannot be used as {_article(what)} name"
            )
            return n.Name(t.pos, t.text)
        raise self._fail(f"expected {_article(what)} name, found {t.describe()}")

    # ------------------------------------------------------------ declarations

    def _parse_type(self) -> str:
        t = self.tok
        if t.kind == "keyword" and t.text in TYPE_BY_NAME:
            self._advance()
            return t.text
        if t.kind == "ident":
            hint = did_you_mean(t.text.upper(), sorted(TYPE_BY_NAME))
            raise self._fail(f"unknown object type '{t.text}'{hint}")
        raise self._fail(
            f"expected an object type, USE, PROCEDURE or END$MODULE, found {t.describe()}"
        )

    # BNF: external_decl = "USE" object_type object_name { "," object_name } ";" ;
    def _parse_external_decl(self) -> n.UseDecl:
        pos = self._advance().pos
        type_kw = self._parse_type()
        names = [self._parse_name("object")]
        while self._accept(","):
            names.append(self._parse_name("object"))
        self._expect(";", "at the end of USE")
        return n.UseDecl(pos, type_kw, tuple(names))

    # BNF: object_decl = object_type object_name "[" [ param_assign { "," param_assign } ] "]" ";" ;
    def _parse_object_decl(self) -> n.ObjectDecl:
        pos = self.tok.pos
        type_kw = self._parse_type()
        name = self._parse_name("object")
        if self._is("{"):
            brace = self._advance()
            self._error(
                brace.pos,
                "an object declaration never contains an index: declare "
                "the whole array and give its length with ARRAY$SIZE",
            )
            while self.tok.kind != "eof" and not self._is("}") and not self._is("["):
                self._advance()
            self._accept("}")
        self._expect("[", f"after the object name '{name.text}' (the parameter list)")
        params: list[n.ParamAssign] = []
        if not self._is("]"):
            params.append(self._parse_param_assign())
            while self._accept(","):
                params.append(self._parse_param_assign())
        self._expect("]", "at the end of the parameter list")
        self._expect(";", "after the declaration")
        return n.ObjectDecl(pos, type_kw, name, tuple(params))

    # BNF: param_assign = param_kwd "=" param_value ;
    def _parse_param_assign(self) -> n.ParamAssign:
        t = self.tok
        if t.kind != "keyword":
            raise self._fail(f"expected a parameter keyword, found {t.describe()}")
        self._advance()
        self._expect("=", f"after the parameter {t.text}")
        return n.ParamAssign(t.pos, t.text, self._parse_param_value())

    # BNF: param_value = [ "-" ] integer_const | keyword | object_name | string [ string ] ;
    def _parse_param_value(self) -> n.ParamValue:
        t = self.tok
        if self._is("-") or self._is("+"):
            sign = -1 if self._advance().text == "-" else 1
            if self.tok.kind != "int":
                raise self._fail(f"expected an integer after '{t.text}'")
            return n.IntValue(t.pos, sign * self._advance().value)  # type: ignore[operator]
        if t.kind == "int":
            self._advance()
            return n.IntValue(t.pos, t.value)  # type: ignore[arg-type]
        if t.kind == "keyword":
            self._advance()
            return n.KeywordValue(t.pos, t.text)
        if t.kind == "ident":
            self._advance()
            return n.NameValue(t.pos, n.Name(t.pos, t.text))
        if t.kind == "string":
            self._advance()
            second = self._advance().value if self.tok.kind == "string" else None
            return n.StringValue(t.pos, t.value, second)  # type: ignore[arg-type]
        raise self._fail(f"expected a parameter value, found {t.describe()}")

    # ------------------------------------------------------------ procedures

    # BNF: procedure = "PROCEDURE" procedure_name ";" activator_decl "BEGIN" { instruction } "END$PROCEDURE" ";" ;
    def _parse_procedure(self) -> n.Procedure:
        pos = self._advance().pos
        name = self._parse_name("procedure")
        self._expect(";", "after the procedure name")
        activators: list[n.ActivatorEntry] = []
        if self._is("DECLARE"):
            activators = self._parse_activator_decl()
        else:
            self._error(
                self.tok.pos, f"procedure '{name.text}' needs an activator list: DECLARE {{ ... }};"
            )
        self._expect("BEGIN", "before the procedure body")
        body = self._parse_block(("END$PROCEDURE",))
        self._expect("END$PROCEDURE", f"at the end of procedure '{name.text}'")
        self._expect(";", "after END$PROCEDURE")
        return n.Procedure(pos, name, tuple(activators), tuple(body))

    # BNF: activator_decl = "DECLARE" "{" activator { "," activator } "}" ";" ;
    def _parse_activator_decl(self) -> list[n.ActivatorEntry]:
        self._advance()
        self._expect("{", "after DECLARE")
        entries = [self._parse_activator()]
        while self._accept(","):
            entries.append(self._parse_activator())
        self._expect("}", "at the end of the activator list")
        self._expect(";", "after the activator list")
        return entries

    # BNF: activator = activator_kwd "OF" object_name [ "{" integer_const "}" ] | global_activator_kwd ;
    def _parse_activator(self) -> n.ActivatorEntry:
        t = self.tok
        if t.kind != "keyword":
            raise self._fail(f"expected an activator (KEYWORD OF object), found {t.describe()}")
        self._advance()
        if t.text in GLOBAL_ACTIVATORS:
            return n.GlobalActivator(t.pos, t.text)
        self._expect("OF", f"after the activator keyword {t.text}")
        obj = self._parse_name("object")
        index = None
        if self._accept("{"):
            if self.tok.kind != "int":
                raise self._fail("an activator subscript must be an integer constant")
            index = self._advance().value
            self._expect("}", "after the subscript")
        return n.ActivatorRef(t.pos, t.text, obj, index)  # type: ignore[arg-type]

    # ------------------------------------------------------------ instructions

    def _parse_block(self, ends: tuple[str, ...]) -> list[n.Instr]:
        body: list[n.Instr] = []
        recovering = False
        while not any(self._is(e) for e in ends):
            t = self.tok
            if t.kind == "keyword" and t.text in STRAY_ENDS:
                # After an error inside an IF or WHILE header, its END is stray here.
                if not recovering:
                    self._error(t.pos, f"{t.text} without a matching {STRAY_ENDS[t.text]}")
                self._advance()
                self._accept(";")
                continue
            if t.kind == "eof" or (t.kind == "keyword" and t.text in BLOCK_ENDS):
                return body
            try:
                body.append(self._parse_instruction())
                recovering = False
            except ParseError:
                self._sync()
                recovering = True
        return body

    # BNF: instruction = assignment | operator_call | if_instr | while_instr | return_instr ;
    def _parse_instruction(self) -> n.Instr:
        t = self.tok
        if self._is("IF"):
            return self._parse_if_instr()
        if self._is("WHILE"):
            return self._parse_while_instr()
        if self._is("RETURN"):
            self._advance()
            self._expect(";", "after RETURN")
            return n.Return(t.pos)
        if t.kind == "keyword" and self.toks[self.k + 1].text == "OF":
            return self._parse_assignment_or_call()
        if t.kind == "ident" and self.toks[self.k + 1].text == "OF":
            hint = did_you_mean(t.text.upper(), sorted(STATE_WORDS | OPERATOR_WORDS))
            raise self._fail(f"'{t.text}' is not a state-variable or operator keyword{hint}")
        if t.kind == "ident":
            raise self._fail(
                f"an instruction cannot start with the name '{t.text}': write a "
                f"state variable as KEYWORD OF {t.text}"
            )
        raise self._fail(f"expected an instruction, found {t.describe()}")

    # BNF: assignment = state_ref "=" expression ";" ;
    # BNF: operator_call = operator_kwd "OF" object_ref [ "(" expression { "," expression } ")" ] ";" ;
    def _parse_assignment_or_call(self) -> n.Instr:
        kw = self._advance()
        self._advance()
        obj = self._parse_object_ref()
        if self._accept("="):
            value = self._parse_expression()
            self._expect(";", "at the end of the assignment")
            return n.Assign(kw.pos, n.StateRef(kw.pos, kw.text, obj), value)
        args: list[n.Expr] = []
        if self._accept("("):
            args.append(self._parse_expression())
            while self._accept(","):
                args.append(self._parse_expression())
            self._expect(")", "at the end of the operator arguments")
        self._expect(";", f"after the operator call {kw.text} (or '=' for an assignment)")
        return n.OperatorCall(kw.pos, kw.text, obj, tuple(args))

    # BNF: if_instr = "IF" expression "THEN" { instruction } [ "ELSE" { instruction } ] "END$IF" ";" ;
    def _parse_if_instr(self) -> n.If:
        self._enter(self.tok)
        try:
            return self._parse_if_body()
        finally:
            self.depth -= 1

    def _parse_if_body(self) -> n.If:
        pos = self._advance().pos
        cond = self._parse_expression()
        self._expect("THEN", "after the IF condition")
        then = self._parse_block(("ELSE", "END$IF"))
        orelse: list[n.Instr] = []
        if self._accept("ELSE"):
            orelse = self._parse_block(("END$IF",))
        self._expect("END$IF", "to close the IF")
        self._expect(";", "after END$IF")
        return n.If(pos, cond, tuple(then), tuple(orelse))

    # BNF: while_instr = "WHILE" expression "DO" { instruction } "END$WHILE" ";" ;
    def _parse_while_instr(self) -> n.While:
        self._enter(self.tok)
        try:
            return self._parse_while_body()
        finally:
            self.depth -= 1

    def _parse_while_body(self) -> n.While:
        pos = self._advance().pos
        cond = self._parse_expression()
        self._expect("DO", "after the WHILE condition")
        body = self._parse_block(("END$WHILE",))
        self._expect("END$WHILE", "to close the WHILE")
        self._expect(";", "after END$WHILE")
        return n.While(pos, cond, tuple(body))

    # BNF: object_ref = object_name [ "{" expression "}" ] ;
    def _parse_object_ref(self) -> n.ObjectRef:
        name = self._parse_name("object")
        index = None
        if self._accept("{"):
            index = self._parse_expression()
            self._expect("}", "after the subscript")
        return n.ObjectRef(name.pos, name, index)

    # ------------------------------------------------------------ expressions

    # BNF: expression = disjunction ;
    # BNF: disjunction = conjunction { "OR" conjunction } ;
    def _parse_expression(self) -> n.Expr:
        left = self._parse_conjunction()
        count = 0
        while self._is("OR"):
            count = self._count(count, self.tok)
            op = self._advance()
            left = n.Binary(op.pos, "OR", left, self._parse_conjunction())
        return left

    # BNF: conjunction = negation { ( "AND" | "&" ) negation } ;
    def _parse_conjunction(self) -> n.Expr:
        left = self._parse_negation()
        count = 0
        while self._is("AND") or self._is("&"):
            count = self._count(count, self.tok)
            op = self._advance()
            left = n.Binary(op.pos, "AND", left, self._parse_negation())
        return left

    # BNF: negation = "NOT" negation | relation ;
    def _parse_negation(self) -> n.Expr:
        if self._is("NOT"):
            self._enter(self.tok)
            try:
                op = self._advance()
                return n.Unary(op.pos, "NOT", self._parse_negation())
            finally:
                self.depth -= 1
        return self._parse_relation()

    # BNF: relation = arith [ rel_op arith ] ;
    def _parse_relation(self) -> n.Expr:
        left = self._parse_arith()
        if self.tok.kind == "delim" and self.tok.text in REL_OPS:
            op = self._advance()
            left = n.Binary(op.pos, op.text, left, self._parse_arith())
            if self.tok.kind == "delim" and self.tok.text in REL_OPS:
                raise self._fail("relations cannot be chained: combine them with AND")
        return left

    # BNF: arith = [ "+" | "-" ] term { ( "+" | "-" ) term } ;
    def _parse_arith(self) -> n.Expr:
        if self._is("-") or self._is("+"):
            op = self._advance()
            left: n.Expr = n.Unary(op.pos, op.text, self._parse_term())
        else:
            left = self._parse_term()
        count = 0
        while self._is("+") or self._is("-"):
            count = self._count(count, self.tok)
            op = self._advance()
            left = n.Binary(op.pos, op.text, left, self._parse_term())
        return left

    # BNF: term = factor { ( "*" | "/" ) factor } ;
    def _parse_term(self) -> n.Expr:
        left = self._parse_factor()
        count = 0
        while self._is("*") or self._is("/"):
            count = self._count(count, self.tok)
            op = self._advance()
            left = n.Binary(op.pos, op.text, left, self._parse_factor())
        return left

    # BNF: factor = integer_const | digital_const | set_const | string | state_ref | object_name | "(" expression ")" ;
    def _parse_factor(self) -> n.Expr:
        t = self.tok
        if t.kind == "int":
            self._advance()
            return n.IntLit(t.pos, t.value)  # type: ignore[arg-type]
        if t.kind == "string":
            self._advance()
            return n.StrLit(t.pos, t.value)  # type: ignore[arg-type]
        if t.kind == "ident":
            self._advance()
            if self._is("{"):
                raise self._fail(
                    f"an array element is not a value: write KEYWORD OF {t.text}{{...}}", t
                )
            return n.NameLit(t.pos, n.Name(t.pos, t.text))
        if self._is("("):
            self._enter(t)
            try:
                self._advance()
                inner = self._parse_expression()
                self._expect(")", "to close '('")
            finally:
                self.depth -= 1
            return inner
        if t.kind == "keyword":
            if self.toks[self.k + 1].text == "OF":
                # BNF: state_ref = state_kwd "OF" object_ref ;
                self._advance()
                self._advance()
                return n.StateRef(t.pos, t.text, self._parse_object_ref())
            if t.text in ("ON", "OFF"):
                self._advance()
                return n.DigitalLit(t.pos, t.text == "ON")
            if t.text in SET_CONSTANTS:
                self._advance()
                return n.SetLit(t.pos, t.text)
        raise self._fail(f"expected an expression, found {t.describe()}")


def parse_tokens(tokens: list[Token], path: str, sink: DiagnosticSink) -> n.GdlFile:
    """Parse one file's tokens; syntax errors go to `sink`."""
    return Parser(tokens, sink).parse_file(path)
