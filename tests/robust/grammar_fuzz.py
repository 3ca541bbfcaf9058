"""Program generators for the grammar-aware fuzz tests: whole HMPL, PDL and GDL programs
built from each language's grammar, with nesting, long expressions, extreme literals and
every statement form, and (sometimes) a small damage to the text so that the error paths
see grammar-shaped input too. Each generator takes a `random.Random` and returns text.
"""

from __future__ import annotations

import random

# ---------------------------------------------------------------- HMPL

HMPL_INT_LITERALS = [
    "0", "1", "-1", "7", "255", "0x7fffffff", "0x80000000", "0xffffffff", "2147483647",
    "-2147483648", "4294967295", "0x7fffffffffffffff", "18446744073709551615u", "1ull",
    "'a'", "'\\x7f'", "'\\0'", "'\\n'", "010", "0777", "1u", "1l", "3ll",
]  # fmt: skip
HMPL_FLOAT_LITERALS = ["0.0", "1.5", "-2.5", "1e308", "1e-320", "3.4e38f", "0.1f", "1e10", "-0.0"]
HMPL_BINOPS = ["+", "-", "*", "/", "%", "<<", ">>", "&", "|", "^", "<", "<=", ">", ">=",
               "==", "!=", "&&", "||"]  # fmt: skip
HMPL_TYPES = ["int", "char", "short", "long", "long long", "unsigned", "unsigned char",
              "unsigned long long", "double", "float"]  # fmt: skip

HMPL_PRELUDE = """struct P { int x; double y; struct P *next; char name[8]; };
typedef struct P Point;
int gi[8];
double gd;
char gs[32] = "seed";
long long gl;
unsigned gu;
Point gp;
int *gptr;
Timer gt;
enum Color { RED, GREEN = 5, BLUE };
"""


class HmplGen:
    def __init__(self, r: random.Random) -> None:
        self.r = r
        self.n = 0
        self.labels = 0

    def int_expr(self, d: int) -> str:
        r = self.r
        if d <= 0 or r.random() < 0.3:
            return r.choice(
                HMPL_INT_LITERALS
                + [
                    "a",
                    "b",
                    "gi[a & 7]",
                    "gl",
                    "gu",
                    "gp.x",
                    "RED",
                    "BLUE",
                    "gs[b & 31]",
                    "(int)gd",
                    "*gptr",
                    "gptr[1]",
                    "gp.next->x",
                    "sizeof(Point)",
                    "StringLen(gs)",
                    "system_timeInMs",
                    "_TASKID_",
                    "__LINE__",
                    "(int[]){a, b, 3}[b & 1]",
                    "(Point){a, 2.5}.x",
                    "(&(struct P){.x = b})->x",
                    "++(int){a}",
                ]  # fmt: skip
            )
        k = r.random()
        if k < 0.45:
            op = r.choice(HMPL_BINOPS)
            right = self.int_expr(d - 1)
            if op in ("/", "%") and r.random() < 0.9:
                right = f"({right} | 1)"  # mostly defined: deeper code gets compiled
            return f"({self.int_expr(d - 1)} {op} {right})"
        if k < 0.55:
            return f"({r.choice(['-', '~', '!', '+'])}{self.int_expr(d - 1)})"
        if k < 0.65:
            return f"(({r.choice(HMPL_TYPES)}){self.any_expr(d - 1)})"
        if k < 0.72:
            return f"({self.int_expr(d - 1)} ? {self.int_expr(d - 1)} : {self.int_expr(d - 1)})"
        if k < 0.8:
            return f"f{r.randrange(3)}({self.int_expr(d - 1)}, {self.int_expr(d - 1)})"
        if k < 0.85:
            return f"({r.choice(['a', 'b', 'gi[2]', 'gp.x'])} {r.choice(['=', '+=', '-=', '*=', '<<=', '|=', '%='])} {self.int_expr(d - 1)})"
        if k < 0.9:
            return r.choice(["a++", "--b", "gi[1]++", "++gp.x"])
        if k < 0.95:  # a long chain
            n = r.choice([20, 200, 1000])
            return (
                "("
                + f" {r.choice(['+', '^', '-'])} ".join(r.choice(["a", "b", "1"]) for _ in range(n))
                + ")"
            )
        return "(" * 40 + self.int_expr(d - 1) + ")" * 40

    def any_expr(self, d: int) -> str:
        if self.r.random() < 0.3:
            return self.r.choice(HMPL_FLOAT_LITERALS + ["gd", "gp.y", "(gd * 2.5)", "(1.0 / gd)"])
        return self.int_expr(d)

    def stmt(self, d: int, in_loop: bool, in_switch: bool) -> str:
        r = self.r
        k = r.random()
        e = self.int_expr
        if d <= 0 or k < 0.25:
            return r.choice(
                [
                    f"a = {e(3)};",
                    f"gd = {self.any_expr(2)};",
                    f'Print("%d %s %f", {e(2)}, gs, gd);',
                    f'StringPrint(gs, "%d", {e(2)});',
                    f"gi[{e(1)} & 7] = {e(2)};",
                    "gptr = &gi[2];",
                    "gp.next = &gp;",
                    f"Sleep({r.choice(['0', '1', '2'])});",
                    "Till(system_timeInMs >= 0);",
                    f"gl = gl * {e(1)} + 1;",
                    ";",
                    # C89 brace elision, C99 compound literals, a prototype in a block
                    f"{{ int m[2][3] = {{a, {e(1)}, 3, {{4}}}}; a = m[1][0] + m[0][1]; }}",
                    f'{{ Point ps[2] = {{a, 1.5, 0, "ab", {e(1)}}}; a = ps[1].x; }}',
                    f"{{ int *q = (int[]){{{e(1)}, 2}}; gptr = q; a = q[1]; }}",
                    'gp = (Point){.x = a, .name = "cl"};',
                    "{ int f9(int); int f1(int, int); a = a + 1; }",
                ]
                + (["break;", "continue;"] if in_loop else [])
                + (["break;"] if in_switch else [])
            )
        self.n += 1
        v = f"i{self.n}"
        if k < 0.4:
            return f"if ({e(2)}) {{ {self.block(d - 1, in_loop, in_switch)} }} else {self.stmt(d - 1, in_loop, in_switch)}"
        if k < 0.5:
            return f"for (int {v} = 0; {v} < {r.randint(0, 4)}; {v}++) {{ {self.block(d - 1, True, False)} }}"
        if k < 0.58:
            return f"{{ int {v} = 0; while ({v}++ < 3) {{ {self.block(d - 1, True, False)} }} }}"
        if k < 0.64:
            return (
                f"{{ int {v} = 0; do {{ {self.block(d - 1, True, False)} }} while (++{v} < 2); }}"
            )
        if k < 0.74:
            cases = " ".join(
                f"case {c}: {self.block(d - 1, in_loop, True)} {r.choice(['break;', ''])}"
                for c in r.sample(range(-3, 10), r.randint(1, 4))
            )
            return f"switch ({e(2)}) {{ {cases} default: a = 1; }}"
        if k < 0.8:
            return f"{{ {r.choice(HMPL_TYPES)} {v} = {self.any_expr(2)}; a = (int){v}; }}"
        if k < 0.9:  # deep nesting
            depth = r.choice([10, 16, 30])
            return "{" * depth + self.stmt(0, in_loop, in_switch) + "}" * depth
        return f"{{ {self.block(d - 1, in_loop, in_switch)} }}"

    def block(self, d: int, in_loop: bool, in_switch: bool) -> str:
        return " ".join(self.stmt(d, in_loop, in_switch) for _ in range(self.r.randint(1, 3)))

    def program(self) -> str:
        r = self.r
        funcs = []
        for k in range(3):
            body = self.block(r.randint(1, 4), False, False)
            jump = "if (a > 100) goto done; " if r.random() < 0.5 else ""
            funcs.append(f"int f{k}(int a, int b) {{ {jump}{body} done: return a + b; }}")
            if r.random() < 0.2:
                funcs.append(f'#line {r.randint(1, 99999)} "renumbered.hmpl"')
        main = f'void main() {{ int a = 1, b = 2; {self.block(r.randint(2, 5), False, False)} Print("%d", a); }}'
        return HMPL_PRELUDE + "\n".join(funcs) + "\n" + main + "\n"


def damage(text: str, r: random.Random) -> str:
    """A small damage: a deleted span, a duplicated span or a stray character."""
    if not text:
        return text
    i = r.randrange(len(text))
    j = min(len(text), i + r.randint(1, 12))
    k = r.random()
    if k < 0.4:
        return text[:i] + text[j:]
    if k < 0.8:
        return text[:j] + text[i:j] + text[j:]
    return (
        text[:i] + r.choice(["{", "}", "(", ")", ";", '"', "'", "\\", "#", "@", "\x00"]) + text[i:]
    )


# ---------------------------------------------------------------- PDL


class PdlGen:
    """PDL: one operator per assignment, `do ... end;` blocks, tasks, procedures."""

    def __init__(self, r: random.Random) -> None:
        self.r = r
        self.labels = 0

    def operand(self) -> str:
        return self.r.choice(
            [
                "s",
                "a",
                "t[1]",
                "t[a]",
                "0",
                "1",
                "-1",
                "0x7FFFFFFF",
                "-2147483648",
                "65535",
                "f",
                "1.5",
                "-0.0",
                "fclk",
            ]  # fmt: skip
        )

    def cond(self) -> str:
        r = self.r
        base = f"{self.operand()} {r.choice(['<', '>', '=', '<>', '<=', '>='])} {self.operand()}"
        if r.random() < 0.2:
            base = f"({base}) & ~(IN1)"
        return base

    def stmt(self, d: int) -> str:
        r = self.r
        k = r.random()
        if d <= 0 or k < 0.35:
            op = r.choice(["+", "-", "*", "/", "&", "|"])
            return r.choice(
                [
                    f"s = {self.operand()} {op} {self.operand()};",
                    f"a = {self.operand()};",
                    f"t[{r.choice(['0', '2', 'a', '9'])}] = {self.operand()};",
                    f"f = {self.operand()} {r.choice(['+', '*'])} {self.operand()};",
                    'printl("%d %d", s, a);',
                    "s++;",
                    "a--;",
                    f"sleep {r.randint(0, 3)};",
                    "OUT1 = IN1;",
                    f"a = max(a, {self.operand()});",
                ]
            )
        if k < 0.55:
            other = f"else do\n{self.block(d - 1)}\n" if r.random() < 0.5 else ""
            return f"if ({self.cond()}) do\n{self.block(d - 1)}\n{other}end;"
        if k < 0.7:
            return f"loop({r.choice(['0', '1', '2', '3', 'a'])}) do\n{self.block(d - 1)}\nend;"
        if k < 0.8:
            return f"a = 0;\nwhile (a < {r.randint(1, 3)}) do\n{self.block(d - 1)}\na++;\nend;"
        if k < 0.88:
            self.labels += 1
            return f"if (s > 1000) goto L{self.labels};\ns++;\nL{self.labels}:"
        if k < 0.94:
            depth = r.choice([10, 25, 60])
            return "loop(1) do\n" * depth + self.stmt(0) + "\n" + "end;\n" * depth
        return "p(s);"

    def block(self, d: int) -> str:
        return "\n".join(self.stmt(d) for _ in range(self.r.randint(1, 3)))

    def program(self) -> str:
        r = self.r
        return (
            "#long s, a, t[10];\n#float f;\n"
            f"proc p(long x) do\n{self.block(r.randint(0, 2))}\nend;\n"
            f"#task/0;\ns = 0; a = 0;\n{self.block(r.randint(1, 4))}\n"
            'printl("%d", s);\nhalt;\n'
            f"#task/1;\n{self.block(r.randint(0, 2))}\nhalt;\n"
        )


# ---------------------------------------------------------------- GDL


class GdlGen:
    """GDL: a module of variables and procedures run by a scenario event."""

    def __init__(self, r: random.Random) -> None:
        self.r = r

    def expr(self, d: int) -> str:
        r = self.r
        if d <= 0 or r.random() < 0.3:
            return r.choice(
                [
                    "VALUE OF s",
                    "VALUE OF a",
                    "VALUE OF v{2}",
                    "0",
                    "1",
                    "(0 - 1)",
                    "999999999",
                    "VALUE OF v{VALUE OF a}",
                    "999999999",
                ]  # fmt: skip
            )
        k = r.random()
        if k < 0.6:
            return f"({self.expr(d - 1)} {r.choice(['+', '-', '*', '/'])} {self.expr(d - 1)})"
        if k < 0.7:
            return f"(0 - {self.expr(d - 1)})"
        if k < 0.85:
            n = r.choice([10, 300, 1000])
            return " + ".join(["VALUE OF a"] * n)
        return "(" * 60 + self.expr(d - 1) + ")" * 60

    def cond(self, d: int) -> str:
        r = self.r
        c = f"{self.expr(d)} {r.choice(['=', '<>', '<', '>', '<=', '>='])} {self.expr(d)}"
        if r.random() < 0.3:
            c = f"NOT ({c}) OR STATUS OF go"
        return c

    def stmt(self, d: int) -> str:
        r = self.r
        k = r.random()
        if d <= 0 or k < 0.4:
            return r.choice(
                [
                    f"VALUE OF s = {self.expr(2)};",
                    f"VALUE OF a = {self.expr(1)};",
                    f"VALUE OF v{{{r.choice(['1', '3', '0', '4', 'VALUE OF a'])}}} = {self.expr(1)};",
                    "STATUS OF go = NOT STATUS OF go;",
                    "RETURN;",
                ]
            )
        if k < 0.65:
            els = f"ELSE\n{self.block(d - 1)}\n" if r.random() < 0.4 else ""
            return f"IF {self.cond(2)} THEN\n{self.block(d - 1)}\n{els}END$IF;"
        if k < 0.85:
            return (
                f"VALUE OF a = 0;\nWHILE VALUE OF a < {r.randint(1, 3)} DO\n{self.block(d - 1)}\n"
                "VALUE OF a = VALUE OF a + 1;\nEND$WHILE;"
            )
        depth = r.choice([10, 25, 40])
        return (
            "WHILE VALUE OF a < 1 DO\n" * depth
            + "VALUE OF a = VALUE OF a + 1;\n"
            + "END$WHILE;\n" * depth
        )

    def block(self, d: int) -> str:
        return "\n".join(self.stmt(d) for _ in range(self.r.randint(1, 3)))

    def program(self) -> str:
        return (
            "MODULE m;\n  INTEGER$VARIABLE s [ ];\n  INTEGER$VARIABLE a [ ];\n"
            "  INTEGER$VARIABLE v [ ARRAY$SIZE = 3 ];\n  DIGITAL$FLAG go [ ];\n"
            "  PROCEDURE p;\n  DECLARE { STATUS OF go };\n  BEGIN\n"
            f"{self.block(self.r.randint(1, 4))}\n"
            "  END$PROCEDURE;\nEND$MODULE;\n"
        )


GDL_SCENARIO = '[[event]]\nat = 0.010\nset = "STATUS OF go"\nvalue = "ON"\n'
