"""PDL parser: hand-written recursive descent from preprocessed tokens to `nodes.Program`.

Each `_parse_<rule>` carries its `# BNF:` line; together they are the PDL grammar
(docs/lang/pdl.md). Errors are reported to the sink and the parser resynchronises at the
next `;` (or enters the `do` block it finds first, so `end`s stay matched). A missing
`;` at the end of a line is reported and assumed, a name on its own line missing its
`:` is reported and taken as a label: one typo, one message.

Whether `x = ...` is a state assignment (form 8) depends on `x` being a system state;
states exist only in the drive's catalog (`sysvars`), so the parser can ask it.
"""

from __future__ import annotations

from motionvm.lang.pdl import nodes as n
from motionvm.lang.pdl import sysvars
from motionvm.lang.pdl.lexer import BUILTIN_FUNCS, Token
from motionvm.source.diagnostics import DiagnosticSink
from motionvm.source.files import SourcePos

MAX_NESTING = 200
"""Combined nesting depth of if/else, while and loop (manual §2.2.8)."""

MAX_PAREN_DEPTH = 1000
"""Parentheses nested in one condition, at most."""
MAX_COND_OPERATORS = 20_000
"""'&' and '|' in one condition, at most."""

BINOPS = ("+", "-", "*", "/", "%", "&", "|", "@")
COMPOUND_OPS = ("+=", "-=", "*=", "/=", "%=", "&=", "|=", "@=")
RELOPS = ("=", "<>", "<", ">", "<=", ">=")
SIMPLE_COMMANDS = ("halt", "ret", "exitproc", "lock", "unlock")
NOT_IN_SINGLE_IF = ("wait", "if", "while", "till", "loop")


class ParseError(Exception):
    """Raised after an error has been reported, to unwind to a statement boundary."""


class Parser:
    """Parses one preprocessed token stream; errors go to `sink`."""

    def __init__(self, toks: list[Token], sink: DiagnosticSink) -> None:
        self.toks = toks
        self.sink = sink
        self.i = 0
        self.depth = 0
        self.paren_depth = 0
        self.in_proc = False
        self.lost = False
        """True once tokens were skipped to recover: the AST is then incomplete."""

    # ------------------------------------------------------------ token helpers

    def peek(self, k: int = 0) -> Token:
        if not k:  # `i` never passes the last token (the 'eof')
            return self.toks[self.i]
        toks, j = self.toks, self.i + k
        return toks[j] if j < len(toks) else toks[-1]

    def next(self) -> Token:
        i = self.i
        t = self.toks[i]
        if i < len(self.toks) - 1:
            self.i = i + 1
        return t

    def prev(self) -> Token:
        return self.toks[max(self.i - 1, 0)]

    def at(self, text: str) -> bool:
        t = self.toks[self.i]
        return t.kind == "punct" and t.text == text

    def at_kw(self, *words: str) -> bool:
        t = self.toks[self.i]
        return t.kind == "keyword" and t.value in words

    @staticmethod
    def describe(t: Token) -> str:
        if t.kind == "eof":
            return "end of file"
        if t.kind == "string":
            return "a string"
        return f"'{t.text}'"

    def report(self, tok: Token, msg: str, pos: SourcePos | None = None) -> None:
        o = tok.origin
        if o is not None:
            msg += (
                f" (in the expansion of macro '{o.name}' defined at "
                f"{o.def_pos.line}:{o.def_pos.col})"
            )
            if tok.text == ";" and o.body_ends_with_semicolon:
                msg += (
                    "; a #define takes everything to the end of the line, so remove the "
                    f"';' from the definition of '{o.name}'"
                )
        self.sink.error(pos or tok.pos, msg)

    def fail(self, tok: Token, msg: str) -> ParseError:
        self.report(tok, msg)
        return ParseError()

    def expect(self, text: str, context: str) -> Token:
        if self.at(text):
            return self.next()
        t = self.peek()
        raise self.fail(t, f"expected '{text}' {context}, found {self.describe(t)}")

    def expect_kw(self, word: str, context: str) -> Token:
        if self.at_kw(word):
            return self.next()
        t = self.peek()
        raise self.fail(t, f"expected '{word}' {context}, found {self.describe(t)}")

    def expect_name(self, what: str) -> Token:
        t = self.peek()
        if t.kind == "name":
            return self.next()
        if t.kind == "keyword":
            raise self.fail(t, f"expected {what}, found the keyword '{t.text}'")
        raise self.fail(t, f"expected {what}, found {self.describe(t)}")

    def end_statement(self) -> None:
        """Consume the `;`; a missing one at the end of a line is reported and assumed."""
        if self.at(";"):
            self.next()
            return
        p, t = self.prev(), self.peek()
        if t.kind == "eof" or t.pos.line != p.pos.line or t.pos.file != p.pos.file:
            where = SourcePos(p.pos.file, p.pos.line, max(p.end_col, 1))
            if p.origin is not None:
                where = p.pos
            self.report(p, "expected ';' at the end of the statement", where)
            return
        after = self.peek(1)
        if (
            p.kind == "int"
            and t.text == ","
            and after.kind == "int"
            and t.pos.col == p.end_col
            and after.pos.col == t.end_col
        ):
            raise self.fail(
                t, f"a decimal number is written with '.', not ',': '{p.text}.{after.text}'"
            )
        raise self.fail(t, f"expected ';' at the end of the statement, found {self.describe(t)}")

    def synchronize(self) -> None:
        """Skip to just after the next `;`, or into the next `do` block, or to `end`/`else`."""
        self.lost = True
        while True:
            t = self.peek()
            if t.kind == "eof" or (t.kind == "keyword" and t.value in ("end", "else")):
                return
            self.next()
            if t.kind == "punct" and t.text == ";":
                return
            if t.kind == "keyword" and t.value == "do":
                self._skip_block()
                return

    def _skip_block(self) -> None:
        """After a `do` whose statement failed: parse (and drop) the block and its `end;`."""
        if self.depth >= MAX_NESTING:
            self._skip_balanced()
            return
        self.depth += 1
        try:
            self._parse_block(("end", "else"))
            while self.at_kw("else"):
                self.next()
                if self.at_kw("do"):
                    self.next()
                self._parse_block(("end", "else"))
            if self.at_kw("end"):
                self.next()
                if self.at(";"):
                    self.next()
        finally:
            self.depth -= 1

    def _skip_balanced(self) -> None:
        """Skip without recursion to the `end` matching an open `do` (for absurd nesting)."""
        open_blocks = 1
        while open_blocks and self.peek().kind != "eof":
            t = self.next()
            if t.kind == "keyword" and t.value == "do":
                open_blocks += 1
            elif t.kind == "keyword" and t.value == "end":
                open_blocks -= 1
        if self.at(";"):
            self.next()

    # ------------------------------------------------------------ program and blocks

    # BNF: program = { top_item } EOF
    def parse_program(self) -> n.Program:
        first = self.peek().pos
        items: list[n.Item] = []
        while self.peek().kind != "eof":
            t = self.peek()
            if t.kind == "keyword" and t.value in ("end", "else"):
                hint = "; a one-line 'if' has no 'else'" if t.value == "else" else ""
                self.report(t, f"'{t.text}' without a matching 'do'{hint}")
                self.next()
                if self.at(";"):
                    self.next()
                continue
            items.extend(self._parse_block(("end", "else")))
        return n.Program(first, tuple(items))

    # BNF: block = { top_item }
    def _parse_block(self, stop: tuple[str, ...]) -> tuple[n.Item, ...]:
        items: list[n.Item] = []
        while True:
            t = self.peek()
            if t.kind == "eof" or (t.kind == "keyword" and t.value in stop):
                return tuple(items)
            start = self.i
            try:
                item = self._parse_top_item()
                if item is not None:
                    items.append(item)
            except ParseError:
                self.synchronize()
            if self.i == start:  # never loop without progress
                self.next()

    # BNF: top_item = var_decl | task_dir | proc | stmt_item
    def _parse_top_item(self) -> n.Item | None:
        t = self.peek()
        if t.kind == "directive":
            if t.value in ("long", "short", "float"):
                return self._parse_var_decl()
            if t.value == "task":
                return self._parse_task_dir()
            raise self.fail(t, f"unknown directive '{t.text}'")
        if t.kind == "keyword" and t.value == "proc":
            return self._parse_proc()
        return self._parse_statement()

    # BNF: task_dir = "#task" "/" int_const ";"
    def _parse_task_dir(self) -> n.TaskDirective:
        head = self.next()
        self.expect("/", "after '#task' (write '#task/2;')")
        t = self.peek()
        if t.kind != "int":
            raise self.fail(
                t, f"expected a task number 0..3 after '#task/', found {self.describe(t)}"
            )
        self.next()
        self.end_statement()
        return n.TaskDirective(head.pos, int(t.value))  # type: ignore[arg-type]

    # BNF: var_decl = ( "#long" | "#short" | "#float" ) { "_ro" | "_lp" "(" const "," const ")" } decl_item { "," decl_item } ";"
    def _parse_var_decl(self) -> n.VarDecl:
        head = self.next()
        read_only = False
        limits = None
        while self.at_kw("_ro", "_lp"):
            opt = self.next()
            if opt.value == "_ro":
                read_only = True
                continue
            self.expect("(", "after '_lp'")
            lo = self._parse_const("a lower limit")
            self.expect(",", "between the two limits of '_lp'")
            hi = self._parse_const("an upper limit")
            self.expect(")", "after the limits of '_lp'")
            limits = (lo, hi)
        items = [self._parse_decl_item()]
        while self.at(","):
            self.next()
            items.append(self._parse_decl_item())
        self.end_statement()
        return n.VarDecl(head.pos, str(head.value), tuple(items), read_only, limits)

    # BNF: decl_item = [ "*" ] name [ "[" int_const "]" ]
    def _parse_decl_item(self) -> n.DeclItem:
        pointer = False
        star = self.peek()
        if self.at("*"):
            self.next()
            pointer = True
        name = self.expect_name("a variable name")
        size = None
        if self.at("["):
            self.next()
            t = self.peek()
            if t.kind != "int":
                raise self.fail(
                    t,
                    f"expected an array size (a positive integer constant), "
                    f"found {self.describe(t)}",
                )
            self.next()
            size = int(t.value)  # type: ignore[arg-type]
            if size < 1:
                self.report(t, f"array size {size} is not a positive number of elements")
                size = 1
            semi = self.peek()
            if semi.text == ";" and semi.origin is not None and self.peek(1).text == "]":
                self.report(semi, "expected ']' after the array size, found ';'")
                self.next()
            self.expect("]", "after the array size")
        return n.DeclItem(star.pos if pointer else name.pos, name.text, size, pointer)

    # BNF: const = [ "-" ] ( int_const | float_const )
    def _parse_const(self, what: str) -> n.IntConst | n.FloatConst:
        t = self.peek()
        sign = 1
        if self.at("-"):
            self.next()
            sign = -1
        c = self.peek()
        if c.kind == "int":
            self.next()
            return n.IntConst(t.pos, _wrap32(sign * int(c.value)))  # type: ignore[arg-type]
        if c.kind == "float":
            self.next()
            return n.FloatConst(t.pos, sign * float(c.value))  # type: ignore[arg-type]
        raise self.fail(c, f"expected {what} (a constant), found {self.describe(c)}")

    # BNF: proc = "proc" name "(" [ param { "," param } ] ")" ( ";" | "do" block "end" ";" )
    def _parse_proc(self) -> n.ProcProto | n.ProcDef:
        head = self.next()
        if self.in_proc or self.depth:
            raise self.fail(
                head, "procedures cannot be nested: 'proc' is only allowed at the top level"
            )
        name = self.expect_name("a procedure name")
        self.expect("(", f"after the procedure name '{name.text}'")
        params: list[n.Param] = []
        if not self.at(")"):
            params.append(self._parse_param())
            while self.at(","):
                self.next()
                params.append(self._parse_param())
        self.expect(")", "after the parameters")
        if self.at(";"):
            self.next()
            return n.ProcProto(head.pos, name.text, tuple(params))
        self.expect_kw("do", f"or ';' after 'proc {name.text}(...)'")
        self.in_proc = True
        try:
            body = self._parse_block(("end",))
        finally:
            self.in_proc = False
        self._expect_end(head, "proc")
        return n.ProcDef(head.pos, name.text, tuple(params), body)

    # BNF: param = ( "long" | "float" ) [ "*" ] name | "instate" name
    def _parse_param(self) -> n.Param:
        t = self.peek()
        if self.at_kw("short"):
            raise self.fail(t, "procedure parameters cannot be 'short' (use 'long')")
        if not self.at_kw("long", "float", "instate"):
            raise self.fail(
                t,
                f"expected a parameter type 'long', 'float' or 'instate', found {self.describe(t)}",
            )
        self.next()
        pointer = False
        if self.at("*"):
            if t.value == "instate":
                raise self.fail(self.peek(), "an 'instate' parameter cannot be a pointer")
            self.next()
            pointer = True
        name = self.expect_name("a parameter name")
        return n.Param(t.pos, str(t.value), name.text, pointer)

    def _expect_end(self, opener: Token, what: str) -> None:
        if self.peek().kind == "eof":
            raise self.fail(opener, f"'{what}' block has no matching 'end'")
        self.expect_kw("end", f"to close the '{what}' block")
        self.end_statement()

    def _nested_block(self, opener: Token, stop: tuple[str, ...]) -> tuple[n.Item, ...]:
        if self.depth >= MAX_NESTING:
            self.report(
                opener,
                f"blocks nested more than {MAX_NESTING} deep (if/else, while "
                "and loop count together)",
            )
            self._skip_balanced()
            raise ParseError()
        self.depth += 1
        try:
            return self._parse_block(stop)
        finally:
            self.depth -= 1

    # ------------------------------------------------------------ statements

    # BNF: label_def = name ":"
    # BNF: single_cmd = statement    (* not wait, if, while, till, loop, a label or state = cond *)
    # BNF: statement = label_def | assign ";" | proc_call | command | ";"
    def _parse_statement(self, single: bool = False) -> n.Item | None:
        t = self.peek()
        if t.kind == "punct" and t.text == ";":
            self.next()
            return None
        if t.kind == "keyword":
            return self._parse_keyword_statement(t, single)
        if t.kind == "name":
            nxt = self.peek(1)
            if nxt.kind == "punct" and nxt.text == ":":
                if single:
                    raise self.fail(t, "a label cannot be the command of a one-line 'if'")
                self.next()
                self.next()
                return n.Label(t.pos, t.text)
            if nxt.kind == "punct" and nxt.text == "(":
                return self._parse_proc_call()
            if (
                nxt.kind == "eof"
                or nxt.pos.line != t.pos.line
                and not (nxt.kind == "punct" and nxt.text in ("=", "[", "++", "--"))
            ):
                self.report(
                    t,
                    f"'{t.text}' alone is not a statement; if it is a label, it "
                    f"needs a ':' ('{t.text}:')",
                )
                self.next()
                return n.Label(t.pos, t.text)
            return self._parse_assignment(single)
        if t.kind == "punct" and t.text == "*":
            return self._parse_assignment(single)
        if t.kind == "directive":
            raise self.fail(t, f"'{t.text}' is not allowed here")
        raise self.fail(t, f"expected a statement, found {self.describe(t)}")

    # BNF: command = "halt" ";" | "ret" ";" | "exitproc" ";" | "lock" ";" | "unlock" ";" | ( "wait" | "sleep" ) simple ";" | "kill" simple ";" | goto_stmt | "call" name ";" | loop_stmt | if_stmt | while_stmt | till_stmt | set_stmt | print_cmd
    def _parse_keyword_statement(self, t: Token, single: bool) -> n.Item | None:
        word = str(t.value)
        if single and word in NOT_IN_SINGLE_IF:
            raise self.fail(
                t,
                f"'{t.text}' is not allowed as the command of a one-line 'if'; "
                f"write 'if (...) do {t.text} ...; end;'",
            )
        if word in SIMPLE_COMMANDS:
            self.next()
            self.end_statement()
            return n.Simple(t.pos, word)
        if word in ("wait", "sleep"):
            self.next()
            amount = self._parse_simple(f"a delay after '{t.text}'")
            self.end_statement()
            return n.Delay(t.pos, word, amount)  # type: ignore[arg-type]
        if word == "kill":
            self.next()
            task = self._parse_simple("a task number after 'kill'")
            self.end_statement()
            return n.Kill(t.pos, task)  # type: ignore[arg-type]
        if word == "goto":
            return self._parse_goto()
        if word == "call":
            self.next()
            label = self.expect_name("a label name after 'call'")
            self.end_statement()
            return n.CallLabel(t.pos, label.text)
        if word == "loop":
            return self._parse_loop()
        if word == "if":
            return self._parse_if()
        if word == "while":
            return self._parse_while()
        if word == "till":
            return self._parse_till()
        if word in ("seton", "setoff", "toggle"):
            return self._parse_set_state()
        if word in ("printl", "prints", "retprintl"):
            return self._parse_print()
        if word in BUILTIN_FUNCS or word in ("sttovar", "sizeof"):
            raise self.fail(t, f"'{t.text}' gives a value: assign it, as in 'v = {word}(...);'")
        if word == "do":
            raise self.fail(t, "'do' without 'if', 'while', 'loop' or 'proc'")
        raise self.fail(t, f"unexpected keyword '{t.text}' at the start of a statement")

    # BNF: goto_stmt = "goto" name [ "[" index "]" ] ";"
    def _parse_goto(self) -> n.Goto:
        head = self.next()
        label = self.expect_name("a label name after 'goto'")
        index = None
        if self.at("["):
            self.next()
            index = self._parse_index(allow_inc=False)
            self.expect("]", "after the index of the indirect goto")
        self.end_statement()
        return n.Goto(head.pos, label.text, index)

    # BNF: loop_stmt = "loop" "(" simple ")" "do" block "end" ";"
    def _parse_loop(self) -> n.Loop:
        head = self.next()
        self.expect("(", "after 'loop' (write 'loop(n) do ... end;')")
        count = self._parse_simple("a loop count")
        self.expect(")", "after the loop count")
        self.expect_kw("do", "after 'loop(...)'")
        body = self._nested_block(head, ("end",))
        self._expect_end(head, "loop")
        return n.Loop(head.pos, count, body)  # type: ignore[arg-type]

    # BNF: if_stmt = "if" "(" cond ")" ( "do" block [ "else" "do" block ] "end" ";" | single_cmd )
    def _parse_if(self) -> n.If:
        head = self.next()
        cond = self._parse_paren_cond("if")
        if not self.at_kw("do"):
            cmd = self._parse_statement(single=True)
            if isinstance(cmd, n.StateAssign):
                self.sink.error(
                    cmd.pos,
                    "a state assignment is not allowed as the command of a "
                    "one-line 'if'; write 'if (...) do ... end;'",
                )
            body = (cmd,) if cmd is not None else ()
            return n.If(head.pos, cond, body, None, True)  # type: ignore[arg-type]
        self.next()
        then_body = self._nested_block(head, ("end", "else"))
        else_body = None
        if self.at_kw("else"):
            els = self.next()
            if self.at_kw("do"):
                self.next()
            else:
                self.report(
                    self.peek(), f"expected 'do' after 'else', found {self.describe(self.peek())}"
                )
            else_body = self._nested_block(els, ("end", "else"))
            while self.at_kw("else"):
                self.report(self.next(), "a second 'else' in one 'if'")
                if self.at_kw("do"):
                    self.next()
                self.lost = True
                self._nested_block(els, ("end", "else"))
        self._expect_end(head, "if")
        return n.If(head.pos, cond, then_body, else_body, False)

    # BNF: while_stmt = "while" "(" cond ")" "do" block "end" ";"
    def _parse_while(self) -> n.While:
        head = self.next()
        cond = self._parse_paren_cond("while")
        self.expect_kw("do", "after 'while (...)'")
        body = self._nested_block(head, ("end",))
        self._expect_end(head, "while")
        return n.While(head.pos, cond, body)

    # BNF: till_stmt = "till" "(" cond ")" ";"
    def _parse_till(self) -> n.Till:
        head = self.next()
        cond = self._parse_paren_cond("till")
        self.end_statement()
        return n.Till(head.pos, cond)

    # BNF: set_stmt = ( "seton" | "setoff" | "toggle" ) ( name | "<" name ">" ) ";"
    def _parse_set_state(self) -> n.SetState:
        head = self.next()
        if self.at("<"):
            target: n.VarRef | n.AngleRef = self._parse_angle()
        else:
            name = self.expect_name(f"a state after '{head.text}'")
            target = n.VarRef(name.pos, name.text)
        self.end_statement()
        return n.SetState(head.pos, str(head.value), target)

    # BNF: print_cmd = ( "printl" | "prints" | "retprintl" ) [ "/" hex [ "/" hex ] ] "(" string { "," operand } ")" ";"
    def _parse_print(self) -> n.Print:
        head = self.next()
        modes: list[int] = []
        while self.at("/"):
            slash = self.next()
            if len(modes) == 2:
                raise self.fail(slash, f"'{head.text}' takes at most two modes (/mode1/mode2)")
            modes.append(self._parse_hex_mode())
        self.expect("(", f"after '{head.text}' and its modes")
        fmt = self.peek()
        if fmt.kind != "string":
            raise self.fail(
                fmt,
                f"expected the format string of '{head.text}' in double "
                f"quotes, found {self.describe(fmt)}",
            )
        self.next()
        args: list[n.Operand] = []
        while self.at(","):
            self.next()
            args.append(self._parse_operand())
        self.expect(")", f"after the arguments of '{head.text}'")
        self.end_statement()
        modes += [0] * (2 - len(modes))
        return n.Print(
            head.pos,
            str(head.value),
            modes[0],
            modes[1],
            n.StringConst(fmt.pos, str(fmt.value)),
            tuple(args),
        )

    # BNF: hex = hex_digit { hex_digit }    (* up to 8 digits, no "0x" needed *)
    def _parse_hex_mode(self) -> int:
        first = self.peek()
        if first.kind not in ("int", "name", "keyword"):
            raise self.fail(
                first, f"expected a hexadecimal mode after '/', found {self.describe(first)}"
            )
        text = self.next().text
        last = first
        while True:
            t = self.peek()
            if (
                t.kind in ("int", "name", "keyword")
                and t.pos.line == last.pos.line
                and t.pos.col == last.end_col
                and t.origin is None
            ):
                text += self.next().text
                last = t
            else:
                break
        digits = text[2:] if text[:2].lower() == "0x" else text
        if not digits or any(c not in "0123456789abcdefABCDEF" for c in digits):
            raise self.fail(first, f"mode '{text}' is not a hexadecimal number")
        if len(digits) > 8:
            raise self.fail(first, f"mode '{text}' has {len(digits)} hexadecimal digits; at most 8")
        return int(digits, 16)

    # BNF: proc_call = name "(" [ operand { "," operand } ] ")" ";"
    def _parse_proc_call(self) -> n.ProcCall:
        name = self.next()
        self.next()
        args: list[n.Operand] = []
        if not self.at(")"):
            args.append(self._parse_operand())
            while self.at(","):
                self.next()
                args.append(self._parse_operand())
        self.expect(")", f"after the arguments of '{name.text}'")
        self.end_statement()
        return n.ProcCall(name.pos, name.text, tuple(args))

    # BNF: assign = lvalue ( "=" rhs | comp_op operand | "++" | "--" ) | state_name "=" cond
    def _parse_assignment(self, single: bool) -> n.Item:
        target = self._parse_lvalue()
        op = self.peek()
        if op.kind == "punct" and op.text in ("++", "--"):
            self.next()
            self.end_statement()
            return n.IncDec(target.pos, target, op.text)
        if op.kind == "punct" and op.text in COMPOUND_OPS:
            self.next()
            value = self._parse_operand()
            self._no_second_operator()
            self.end_statement()
            return n.Assign(target.pos, target, op.text, value)
        if not (op.kind == "punct" and op.text == "="):
            raise self.fail(
                op,
                f"expected '=', a compound operator, '++' or '--' after "
                f"the variable, found {self.describe(op)}",
            )
        self.next()
        if self.at("="):
            raise self.fail(
                self.peek(), "'==' is not PDL: '=' assigns, and inside a condition '=' compares"
            )
        if isinstance(target, n.VarRef) and target.index is None and sysvars.is_state(target.name):
            cond = self._parse_cond()
            self.end_statement()
            return n.StateAssign(target.pos, target, cond)
        value = self._parse_rhs()
        self.end_statement()
        return n.Assign(target.pos, target, "=", value)

    # BNF: lvalue = var_ref | deref
    def _parse_lvalue(self) -> n.VarRef | n.Deref:
        if self.at("*"):
            return self._parse_deref()
        return self._parse_var_ref()

    # BNF: rhs = "{" const { "," const } "}" | string | "sttovar" cond | "sizeof" "(" name ")" | "-" var_ref | func_name "(" operand { "," operand } ")" | operand [ binop operand ]
    def _parse_rhs(self) -> n.Value:
        t = self.peek()
        if self.at("{"):
            self.next()
            values = [self._parse_const("an initialiser value")]
            while self.at(","):
                self.next()
                values.append(self._parse_const("an initialiser value"))
            self.expect("}", "after the initialiser values")
            return n.InitList(t.pos, tuple(values))
        if t.kind == "keyword" and t.value == "sttovar":
            self.next()
            return n.SttoVar(t.pos, self._parse_cond())
        if t.kind == "keyword" and t.value == "sizeof":
            self.next()
            self.expect("(", "after 'sizeof'")
            name = self.expect_name("a variable name in 'sizeof(...)'")
            self.expect(")", "after the name in 'sizeof(...)'")
            return n.SizeOf(t.pos, name.text)
        if t.kind == "keyword" and t.value in BUILTIN_FUNCS:
            return self._parse_func_call()
        if t.kind == "punct" and t.text in ("~", "("):
            raise self.fail(
                t,
                "a condition cannot be assigned to a variable directly; write "
                "'v = sttovar <condition>;' to store it as 0 or 1",
            )
        if self.at("-") and self.peek(1).kind not in ("int", "float"):
            self.next()
            operand = self._parse_lvalue()
            self._no_second_operator()
            return n.Neg(t.pos, operand)
        left = self._parse_operand()
        if isinstance(left, n.VarRef) and left.index is None and sysvars.is_state(left.name):
            nxt = self.peek()
            if nxt.kind == "punct" and nxt.text in ("&", "|", ";"):
                raise self.fail(
                    t,
                    f"'{left.name}' is a state, not a value: write "
                    f"'v = sttovar {left.name} ...;' to store a condition as 0 or 1",
                )
        op = self.peek()
        if op.kind == "punct" and op.text in BINOPS:
            self.next()
            right = self._parse_operand()
            self._no_second_operator()
            return n.BinOp(op.pos, op.text, left, right)
        return left

    def _no_second_operator(self) -> None:
        t = self.peek()
        if t.kind == "punct" and t.text in BINOPS:
            raise self.fail(
                t,
                "PDL allows one operator per assignment; split the calculation "
                "into several statements (tmp = a + b; c = tmp * d;)",
            )

    # BNF: func_call = func_name "(" operand { "," operand } ")"
    def _parse_func_call(self) -> n.FuncCall:
        name = self.next()
        self.expect("(", f"after '{name.text}'")
        args = [self._parse_operand()]
        while self.at(","):
            self.next()
            args.append(self._parse_operand())
        self.expect(")", f"after the arguments of '{name.text}'")
        return n.FuncCall(name.pos, str(name.value), tuple(args))

    # BNF: simple = int_const | var_ref    (* a deref is parsed to be rejected by the checker *)
    def _parse_simple(self, what: str) -> n.Operand:
        t = self.peek()
        if t.kind in ("int", "float", "name") or (t.kind == "punct" and t.text in "-*"):
            return self._parse_operand()
        raise self.fail(t, f"expected {what} (a constant or a variable), found {self.describe(t)}")

    # BNF: operand = const | var_ref | deref | "&" var_ref | "<" name ">" | string
    def _parse_operand(self) -> n.Operand:
        t = self.peek()
        if t.kind in ("int", "float") or (self.at("-") and self.peek(1).kind in ("int", "float")):
            return self._parse_const("a value")
        if t.kind == "string":
            self.next()
            return n.StringConst(t.pos, str(t.value))
        if self.at("&"):
            self.next()
            return n.AddressOf(t.pos, self._parse_var_ref())
        if self.at("<"):
            return self._parse_angle()
        if self.at("*"):
            return self._parse_deref()
        if self.at("-"):
            raise self.fail(
                t,
                "'-variable' is only allowed alone on the right of '=' "
                "(v = -w;); negate into a variable first",
            )
        return self._parse_var_ref()

    # BNF: angle = "<" name ">"
    def _parse_angle(self) -> n.AngleRef:
        lt = self.next()
        name = self.expect_name("a state, label or variable name inside '<...>'")
        self.expect(">", f"after '<{name.text}'")
        return n.AngleRef(lt.pos, name.text)

    # BNF: var_ref = name [ "[" index [ "+" ] "]" ]
    def _parse_var_ref(self) -> n.VarRef:
        name = self.expect_name("a variable name")
        if not self.at("["):
            return n.VarRef(name.pos, name.text)
        self.next()
        index = self._parse_index(allow_inc=True)
        inc = False
        if self.at("+") and self.peek(1).kind == "punct" and self.peek(1).text == "]":
            self.next()
            inc = True
        self.expect("]", "after the index")
        if inc and not isinstance(index, n.VarRef):
            self.report(
                name, "an auto-increment index '[n+]' needs a short/long variable, not a constant"
            )
        return n.VarRef(name.pos, name.text, index, inc)

    # BNF: deref = "*" name [ "[" index "]" ]
    def _parse_deref(self) -> n.Deref:
        star = self.next()
        name = self.expect_name("a pointer name after '*'")
        index = None
        if self.at("["):
            self.next()
            index = self._parse_index(allow_inc=False)
            self.expect("]", "after the index")
        return n.Deref(star.pos, name.text, index)

    # BNF: index = int_const | name
    def _parse_index(self, allow_inc: bool) -> n.IntConst | n.VarRef:
        t = self.peek()
        if t.kind == "int":
            self.next()
            return n.IntConst(t.pos, int(t.value))  # type: ignore[arg-type]
        if t.kind == "name":
            self.next()
            nxt, after = self.peek(), self.peek(1)
            if (
                nxt.kind == "punct"
                and nxt.text in BINOPS
                and not (allow_inc and nxt.text == "+" and after.text == "]")
            ):
                raise self.fail(
                    nxt,
                    f"an index is a constant or a short/long variable; "
                    f"compute '{t.text}{nxt.text}...' into a variable first",
                )
            return n.VarRef(t.pos, t.text)
        if t.kind == "punct" and t.text == "-":
            raise self.fail(t, "an index cannot be negative")
        raise self.fail(
            t, f"an index is a constant or a short/long variable, found {self.describe(t)}"
        )

    # ------------------------------------------------------------ conditions

    # BNF: paren_cond = "(" cond ")"
    def _parse_paren_cond(self, what: str) -> n.Cond:
        self.expect("(", f"after '{what}' (the condition is written in parentheses)")
        cond = self._parse_cond()
        self.expect(")", f"to close the condition of '{what}'")
        return cond

    # BNF: cond = cterm { ( "&" | "|" ) cterm }
    def _parse_cond(self) -> n.Cond:
        start = self.peek().pos
        first = self._parse_cterm()
        terms = [first]
        ops: list[str] = []
        while self.peek().kind == "punct" and self.peek().text in ("&", "|"):
            op = self.next()
            if len(ops) >= MAX_COND_OPERATORS:
                raise self.fail(
                    op,
                    f"more than {MAX_COND_OPERATORS} '&' and '|' in one condition (the limit of PDL)",
                )
            if ops and op.text != ops[-1] and len(set(ops)) == 1:
                self.sink.warning(
                    op.pos,
                    "'&' and '|' have equal precedence in PDL and are "
                    "evaluated left to right; add parentheses",
                )
            ops.append(op.text)
            terms.append(self._parse_cterm())
        if not ops:
            return first
        return n.Logic(start, tuple(terms), tuple(ops))

    # BNF: cterm = "~" cneg | catom
    # BNF: cneg = state_name | "<" name ">" | "(" cond ")"
    def _parse_cterm(self) -> n.Cond:
        if not self.at("~"):
            return self._parse_catom()
        tilde = self.next()
        if self.at("("):
            return n.Not(tilde.pos, self._parse_group())
        t = self.peek()
        if self.at("<"):
            ref: n.VarRef | n.AngleRef = self._parse_angle()
        elif t.kind == "name":
            ref = self._parse_var_ref()
        else:
            raise self.fail(
                t,
                f"'~' must be followed by a state, '<var>' or '(condition)', "
                f"found {self.describe(t)}",
            )
        nxt = self.peek()
        if (nxt.kind == "punct" and nxt.text in RELOPS) or (
            nxt.kind == "keyword" and nxt.value == "tout"
        ):
            raise self.fail(
                tilde,
                "'~' applies to a state or a parenthesised condition; "
                "write '~(a > b)' to negate a relation",
            )
        return n.Not(tilde.pos, n.StateTest(ref.pos, ref))

    # BNF: group = "(" cond ")"    (* at most 1000 deep *)
    def _parse_group(self) -> n.Cond:
        lp = self.next()
        if self.paren_depth >= MAX_PAREN_DEPTH:
            raise self.fail(lp, f"parentheses nested more than {MAX_PAREN_DEPTH} deep")
        self.paren_depth += 1
        try:
            cond = self._parse_cond()
        finally:
            self.paren_depth -= 1
        self.expect(")", "to close the parenthesised condition")
        return cond

    def _no_arithmetic(self) -> None:
        t = self.peek()
        if t.kind == "punct" and t.text in ("+", "-", "*", "/", "%", "@"):
            raise self.fail(
                t,
                f"a condition cannot contain arithmetic ('{t.text}'); compute "
                "the value into a variable first (tmp = a + b;)",
            )

    # BNF: catom = "(" cond ")" | operand relop operand | var_ref "TOUT" operand | var_ref "->" int_const | state_name | "<" name ">"
    def _parse_catom(self) -> n.Cond:
        if self.at("("):
            return self._parse_group()
        t = self.peek()
        left = self._parse_operand()
        self._no_arithmetic()
        op = self.peek()
        if op.kind == "punct" and op.text in RELOPS or op.kind == "keyword" and op.value == "tout":
            self.next()
            right = self._parse_operand()
            self._no_arithmetic()
            opname = "TOUT" if op.kind == "keyword" else op.text
            return n.Relation(op.pos, opname, left, right)
        if op.kind == "punct" and op.text == "->":
            self.next()
            bit = self.peek()
            if bit.kind != "int" or not isinstance(left, n.VarRef):
                raise self.fail(bit, "'var->n' tests bit n (a constant 0..31) of a variable")
            self.next()
            return n.BitTest(op.pos, left, int(bit.value))  # type: ignore[arg-type]
        if isinstance(left, (n.VarRef, n.AngleRef)):
            return n.StateTest(left.pos, left)
        raise self.fail(
            t, f"expected a condition (a state, '<var>' or a comparison), found {self.describe(t)}"
        )


def _wrap32(v: int) -> int:
    return ((v + 0x80000000) & 0xFFFFFFFF) - 0x80000000


def parse(toks: list[Token], sink: DiagnosticSink) -> tuple[n.Program, bool]:
    """Parse preprocessed tokens: the Program holds whatever parsed, errors are in `sink`.

    The flag is True if recovery skipped tokens (the Program then misses statements);
    errors repaired in place (a missing ';' or ':') leave it False.
    """
    parser = Parser(toks, sink)
    program = parser.parse_program()
    return program, parser.lost
