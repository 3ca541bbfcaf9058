"""HMPL parser: declarations, types, statements and expressions build the right AST."""

from __future__ import annotations

import pytest

from motionvm.lang.hmpl import nodes as n
from motionvm.lang.hmpl.dump import dump_ast, dump_tokens
from motionvm.lang.hmpl.parser import parse_file
from motionvm.lang.hmpl.preprocess import preprocess
from motionvm.source import DiagnosticSink


def parse_ok(text: str, task_id: int = 0) -> n.TranslationUnit:
    sink = DiagnosticSink()
    tu = parse_file("p.hmpl", task_id=task_id, sink=sink, text=text)
    assert [d.headline() for d in sink.items] == []
    assert tu is not None
    return tu


def body(text: str) -> tuple:
    """The block items of `void f() { text }`."""
    tu = parse_ok("void f() {\n" + text + "\n}")
    fn = tu.items[0]
    assert isinstance(fn, n.FuncDef) and fn.body is not None
    return fn.body.items


def expr(text: str) -> n.Expr:
    (stmt,) = body(text + ";")
    assert isinstance(stmt, n.ExprStmt)
    return stmt.expr


def sx(e) -> str:
    """An expression as a compact S-expression."""
    if isinstance(e, n.Name):
        return e.id
    if isinstance(e, (n.IntLit, n.CharLit)):
        return str(e.value)
    if isinstance(e, n.FloatLit):
        return repr(e.value) + ("f" if e.is_float else "")
    if isinstance(e, n.StrLit):
        return repr(e.value)
    if isinstance(e, n.Binary):
        return f"({e.op} {sx(e.left)} {sx(e.right)})"
    if isinstance(e, n.Assign):
        return f"({e.op} {sx(e.target)} {sx(e.value)})"
    if isinstance(e, n.Unary):
        return f"({e.op} {sx(e.operand)})"
    if isinstance(e, n.Postfix):
        return f"(post{e.op} {sx(e.operand)})"
    if isinstance(e, n.Cond):
        return f"(? {sx(e.cond)} {sx(e.then)} {sx(e.else_)})"
    if isinstance(e, n.Comma):
        return "(, " + " ".join(sx(x) for x in e.items) + ")"
    if isinstance(e, n.Call):
        return "(call " + " ".join(sx(x) for x in (e.func, *e.args)) + ")"
    if isinstance(e, n.Index):
        return f"([] {sx(e.base)} {sx(e.index)})"
    if isinstance(e, n.Member):
        return f"({'->' if e.arrow else '.'} {sx(e.base)} {e.name})"
    if isinstance(e, n.Cast):
        return f"(cast {tx(e.type)} {sx(e.expr)})"
    if isinstance(e, n.SizeOf):
        target = tx(e.target) if isinstance(e.target, n.TypeRef) else sx(e.target)
        dims = "".join(f"[{sx(d)}]" for d in e.dims)
        return f"(sizeof {target}{dims})"
    raise AssertionError(e)


def tx(t: n.TypeRef) -> str:
    return ("const " if t.is_const else "") + t.base + "*" * t.pointers


# ---------------------------------------------------------------- expressions


@pytest.mark.parametrize(
    "source, tree",
    [
        ("a + b * c", "(+ a (* b c))"),
        ("a * b + c", "(+ (* a b) c)"),
        ("a - b - c", "(- (- a b) c)"),
        ("a / b % c", "(% (/ a b) c)"),
        ("a << 1 + 2", "(<< a (+ 1 2))"),
        ("a < b == c > d", "(== (< a b) (> c d))"),
        ("a & b == c", "(& a (== b c))"),
        ("a | b ^ c & d", "(| a (^ b (& c d)))"),
        ("a || b && c", "(|| a (&& b c))"),
        ("a && b || c && d", "(|| (&& a b) (&& c d))"),
        ("a = b = c", "(= a (= b c))"),
        ("a += b -= c", "(+= a (-= b c))"),
        ("x <<= 2", "(<<= x 2)"),
        ("x >>= 2", "(>>= x 2)"),
        ("x &= 1, y |= 2, z ^= 3", "(, (&= x 1) (|= y 2) (^= z 3))"),
        ("x *= 2", "(*= x 2)"),
        ("x /= 2", "(/= x 2)"),
        ("x %= 2", "(%= x 2)"),
        ("a ? b : c ? d : e", "(? a b (? c d e))"),
        ("a ? b, c : d", "(? a (, b c) d)"),
        ("x = a ? b : c", "(= x (? a b c))"),
        ("a || b ? c : d", "(? (|| a b) c d)"),
        ("-a * b", "(* (- a) b)"),
        ("-~!a", "(- (~ (! a)))"),
        ("+a", "(+ a)"),
        ("*p++", "(* (post++ p))"),
        ("++*p", "(++ (* p))"),
        ("--x", "(-- x)"),
        ("x--", "(post-- x)"),
        ("&a[3]", "(& ([] a 3))"),
        ("a[i][j]", "([] ([] a i) j)"),
        ("s.p->x", "(-> (. s p) x)"),
        ("f(1, g(2), h())", "(call f 1 (call g 2) (call h))"),
        ("(a + b) * c", "(* (+ a b) c)"),
        ("(int)x + 1", "(+ (cast int32_t x) 1)"),
        ("(double)(int)x", "(cast double (cast int32_t x))"),
        ("(unsigned char *)p", "(cast uint8_t* p)"),
        ("(Timer *)p", "(cast Timer* p)"),
        ("(const char *)s", "(cast const char* s)"),
        ("(x) + 1", "(+ x 1)"),
        ("(int)-x", "(cast int32_t (- x))"),
        ("sizeof(int)", "(sizeof int32_t)"),
        ("sizeof(double[3])", "(sizeof double[3])"),
        ("sizeof x", "(sizeof x)"),
        ("sizeof(x) * 2", "(* (sizeof x) 2)"),
        ("sizeof a[0]", "(sizeof ([] a 0))"),
        ("sizeof(struct P)", "(sizeof struct P)"),
        ('"ab" "cd"', "b'abcd'"),
        ("'A' + 1", "(+ 65 1)"),
        ("1.5f + 2.0", "(+ 1.5f 2.0)"),
        (
            "HIMC_GPO(1) = HIMC_GPI(4) && HIMC_GPI(6)",
            "(= (call HIMC_GPO 1) (&& (call HIMC_GPI 4) (call HIMC_GPI 6)))",
        ),
        (
            "Till(IsEnabled(0) && IsEnabled(1))",
            "(call Till (&& (call IsEnabled 0) (call IsEnabled 1)))",
        ),
        ("a+++b", "(+ (post++ a) b)"),
    ],
)
def test_expression_precedence(source, tree):
    assert sx(expr(source)) == tree


def test_literal_nodes():
    e = expr("x = 0x10u + 2.5f + 'a' + 7ull")
    assert isinstance(e, n.Assign)
    lits = []

    def walk(x):
        if isinstance(x, n.Binary):
            walk(x.left)
            walk(x.right)
        else:
            lits.append(x)

    walk(e.value)
    assert [type(x).__name__ for x in lits] == ["IntLit", "FloatLit", "CharLit", "IntLit"]
    assert (lits[0].value, lits[0].suffix) == (16, "u")
    assert (lits[1].value, lits[1].is_float) == (2.5, True)
    assert lits[2].value == 97
    assert (lits[3].value, lits[3].suffix) == (7, "ull")


def test_expression_positions():
    e = expr("x = a + b[i]")
    assert isinstance(e, n.Assign) and (e.pos.line, e.pos.col) == (2, 3)
    assert isinstance(e.value, n.Binary) and e.value.pos.col == 7
    assert isinstance(e.value.right, n.Index) and e.value.right.pos.col == 10
    call = expr("  Print(x)")
    assert isinstance(call, n.Call) and call.pos.col == 3


# ---------------------------------------------------------------- types


@pytest.mark.parametrize(
    "spelled, base",
    [
        ("char", "char"),
        ("signed char", "char"),
        ("unsigned char", "uint8_t"),
        ("short", "int16_t"),
        ("short int", "int16_t"),
        ("signed short", "int16_t"),
        ("unsigned short", "uint16_t"),
        ("unsigned short int", "uint16_t"),
        ("int", "int32_t"),
        ("signed", "int32_t"),
        ("signed int", "int32_t"),
        ("unsigned", "uint32_t"),
        ("unsigned int", "uint32_t"),
        ("int unsigned", "uint32_t"),
        ("long", "int32_t"),
        ("long int", "int32_t"),
        ("unsigned long", "uint32_t"),
        ("long long", "int64_t"),
        ("long long int", "int64_t"),
        ("signed long long", "int64_t"),
        ("unsigned long long", "uint64_t"),
        ("float", "float"),
        ("double", "double"),
        ("long double", "double"),
        ("int8_t", "int8_t"),
        ("uint8_t", "uint8_t"),
        ("int16_t", "int16_t"),
        ("uint16_t", "uint16_t"),
        ("int32_t", "int32_t"),
        ("uint32_t", "uint32_t"),
        ("int64_t", "int64_t"),
        ("uint64_t", "uint64_t"),
        ("Timer", "Timer"),
        ("Data_t", "Data_t"),
    ],
)
def test_type_canonicalisation(spelled, base):
    (d,) = parse_ok(f"{spelled} v;").items
    assert isinstance(d, n.VarDecl) and d.type.base == base and d.type.pointers == 0


def test_pointers_and_const():
    items = parse_ok("const int *p; int const c = 1; char **pp; int * const q = 0;").items
    assert [(d.name, d.type.base, d.type.pointers, d.type.is_const) for d in items] == [
        ("p", "int32_t", 1, True),
        ("c", "int32_t", 0, True),
        ("pp", "char", 2, False),
        ("q", "int32_t", 1, False),
    ]


# ---------------------------------------------------------------- declarations


def test_global_declarations_with_initializers():
    tu = parse_ok(
        "int a = 1, b[3] = {1, 2, 3}, *c;\n"
        'char msg[] = "hi";\n'
        'char s2[] = {"abc"};\n'
        "int m[][2] = {{1, 2}, {3, 4}, {5, 6}};\n"
        "int flat[][2] = {1, 2, 3, 4, 5};\n"
        "double d[2][3] = {{1.0}, {2.0, 3.0}};\n"
        "int e[4] = {1, 2,};\n"
        "int empty[2] = {};\n"
    )
    decls = {d.name: d for d in tu.items}
    assert list(decls) == ["a", "b", "c", "msg", "s2", "m", "flat", "d", "e", "empty"]
    assert isinstance(decls["a"].init, n.IntLit)
    assert [sx(x) for x in decls["b"].dims] == ["3"]
    assert isinstance(decls["b"].init, n.InitList) and len(decls["b"].init.items) == 3
    assert decls["c"].type.pointers == 1 and decls["c"].init is None
    assert sx(decls["msg"].dims[0]) == "3"  # "hi" plus its NUL
    assert sx(decls["s2"].dims[0]) == "4"
    assert [sx(x) for x in decls["m"].dims] == ["3", "2"]
    assert [sx(x) for x in decls["flat"].dims] == ["3", "2"]
    assert isinstance(decls["d"].init, n.InitList)
    assert isinstance(decls["d"].init.items[1], n.InitList)
    assert len(decls["e"].init.items) == 2
    assert decls["empty"].init == n.InitList(decls["empty"].init.pos, ())


def test_unsized_array_without_initializer_keeps_none():
    (d,) = parse_ok("extern int x; int a[] ;").items
    assert d.name == "a" and d.dims == (None,)


def test_function_definitions_and_prototypes():
    tu = parse_ok(
        "int add(int a, int b);\n"
        "void nothing(void);\n"
        "double *pick(double arr[], int n, Timer *t, char **argv) { return arr; }\n"
        "int proto_unnamed(int, double *);\n"
        "_AUTORUN_ void main() { }\n"
    )
    add, nothing, pick, unnamed, main = tu.items
    assert add.body is None and [p.name for p in add.params] == ["a", "b"]
    assert nothing.params == () and nothing.ret.base == "void"
    assert pick.ret == n.TypeRef(pick.ret.pos, "double", 1)
    assert [(p.name, tx(p.type), p.dims) for p in pick.params] == [
        ("arr", "double", (None,)),
        ("n", "int32_t", ()),
        ("t", "Timer*", ()),
        ("argv", "char**", ()),
    ]
    assert [p.name for p in unnamed.params] == ["", ""]
    assert main.autorun and main.name == "main" and main.body == n.Block(main.body.pos, ())
    assert not pick.autorun


def test_struct_union_and_typedef():
    tu = parse_ok(
        "struct Point { double x, y; };\n"
        "typedef struct Point Point;\n"
        "typedef struct { int id; struct Point where[2]; } Item;\n"
        "union Num { int i; float f; } num;\n"
        "typedef unsigned char byte;\n"
        "typedef int Vec3[3];\n"
        "Point p = {1.0, 2.0};\n"
        "Item *items;\n"
        "byte b = (byte)300;\n"
        "struct Point q;\n"
    )
    kinds = [type(x).__name__ for x in tu.items]
    assert kinds == [
        "StructDef",
        "Typedef",
        "Typedef",
        "StructDef",
        "VarDecl",
        "Typedef",
        "Typedef",
        "VarDecl",
        "VarDecl",
        "VarDecl",
        "VarDecl",
    ]
    point, td_point, td_item, num_def, num, td_byte, td_vec, p, items, b, q = tu.items
    assert (point.kind, point.tag, [f.name for f in point.fields]) == (
        "struct",
        "Point",
        ["x", "y"],
    )
    assert (td_point.name, td_point.type.base) == ("Point", "struct Point")
    assert td_item.type.base == "struct" and td_item.type.struct_def is not None
    assert td_item.type.struct_def.tag == ""
    assert [f.name for f in td_item.type.struct_def.fields] == ["id", "where"]
    assert td_item.type.struct_def.fields[1].type.base == "struct Point"
    assert (num_def.kind, num.type.base, num.type.struct_def) == ("union", "union Num", num_def)
    assert td_byte.type.base == "uint8_t"
    assert sx(td_vec.dims[0]) == "3"
    assert p.type.base == "Point" and isinstance(p.init, n.InitList)
    assert items.type == n.TypeRef(items.type.pos, "Item", 1)
    assert isinstance(b.init, n.Cast) and b.init.type.base == "byte"
    assert q.type.base == "struct Point" and q.type.struct_def is None


def test_extern_declarations_declare_nothing():
    tu = parse_ok("extern int shared; extern double f(double);")
    assert [type(x).__name__ for x in tu.items] == ["FuncDef"]


def test_taskid_and_manual_example_19_1():
    text = """
#if _TASKID_ == 0
int global_var = 0; // 當前 task ID 為 0 才會被編譯
#endif

void test(){

    for (;;) {
        if (HIMC_GPI(1)) {
            StopTask( _TASKID_ ); // 停止當前的 task
        }
    }
}

void main() {
    test();
}
"""
    t0 = parse_ok(text, task_id=0)
    t1 = parse_ok(text, task_id=1)
    assert [x.name for x in t0.items] == ["global_var", "test", "main"]
    assert [x.name for x in t1.items] == ["test", "main"]
    loop = t1.items[0].body.items[0]
    assert isinstance(loop, n.For) and loop.init is None and loop.cond is None
    call = loop.body.items[0].then.items[0].expr
    assert sx(call) == "(call StopTask 1)"


# ---------------------------------------------------------------- statements


def test_statements():
    items = body(
        """
        int i = 0, j;
        ;
        { j = 1; }
        if (i) j = 2; else if (j) j = 3; else { j = 4; }
        while (i < 10) i++;
        do { i--; } while (i > 0);
        for (int k = 0; k < 3; ++k) continue;
        for (i = 0, j = 1; ; ) break;
        for (;;) {}
        switch (i) { case 1: case 2 + 1: j = 5; break; default: j = 6; }
        return;
        """
    )
    kinds = [type(s).__name__ for s in items]
    assert kinds == [
        "DeclStmt",
        "Empty",
        "Block",
        "If",
        "While",
        "DoWhile",
        "For",
        "For",
        "For",
        "Switch",
        "Return",
    ]
    decl, _, _, if_, while_, do, for1, for2, for3, switch, ret = items
    assert [d.name for d in decl.decls] == ["i", "j"]
    assert isinstance(if_.else_, n.If) and isinstance(if_.else_.else_, n.Block)
    assert isinstance(while_.body, n.ExprStmt)
    assert sx(do.cond) == "(> i 0)"
    assert isinstance(for1.init, n.DeclStmt) and sx(for1.step) == "(++ k)"
    assert isinstance(for1.body, n.Continue)
    assert isinstance(for2.init, n.ExprStmt) and sx(for2.init.expr) == "(, (= i 0) (= j 1))"
    assert for2.cond is None and for2.step is None and isinstance(for2.body, n.Break)
    assert for3.body == n.Block(for3.body.pos, ())
    assert [type(s).__name__ for s in switch.body.items] == [
        "Case",
        "Case",
        "ExprStmt",
        "Break",
        "Default",
        "ExprStmt",
    ]
    assert sx(switch.body.items[1].value) == "(+ 2 1)"
    assert ret.value is None


def test_dangling_else_binds_to_the_nearest_if():
    (outer,) = body("if (a) if (b) x = 1; else x = 2;")
    assert outer.else_ is None and outer.then.else_ is not None


def test_return_value_and_declarations_anywhere():
    items = body("x = 1; int y = x; return y * 2;")
    assert [type(s).__name__ for s in items] == ["ExprStmt", "DeclStmt", "Return"]
    assert sx(items[2].value) == "(* y 2)"


def test_goto_and_labels():
    items = body("goto done; x = 1;\ndone:\n  return;\nagain: ;")
    assert [type(s).__name__ for s in items] == [
        "Goto",
        "ExprStmt",
        "Label",
        "Return",
        "Label",
        "Empty",
    ]
    assert items[0].label == "done" and items[2].name == "done"


def test_local_struct_variables_and_typedef_names():
    tu = parse_ok(
        "typedef struct { int a; } T;\n"
        "void f() { T t; T *pt = &t; Timer tm = TimerInit; Data_t d; d.int32_ = 5; "
        "pt->a = sizeof(T); }"
    )
    items = tu.items[1].body.items
    assert [type(s).__name__ for s in items] == [
        "DeclStmt",
        "DeclStmt",
        "DeclStmt",
        "DeclStmt",
        "ExprStmt",
        "ExprStmt",
    ]
    assert sx(items[5].expr) == "(= (-> pt a) (sizeof T))"


def test_manual_example_2_23_ton():
    text = """
void main()
{
    // 初始化計數器
    Timer timer1 = TimerInit;
    Timer timer2 = TimerInit;

    int counter = 0;
    int target_cnt = 1000;
    int cnt_reach_delay_1s = 0;
    int cnt_reach_delay_3s = 0;

    for (;;) {
        Sleep(1);
        counter = counter + 1;
        cnt_reach_delay_1s = TON(&timer1, counter >= target_cnt, 1000);
        cnt_reach_delay_3s = TON(&timer2, cnt_reach_delay_1s, 2000);

        system_dtest0 = counter;
        system_dtest1 = target_cnt;

        if(cnt_reach_delay_3s){
            Sleep(500);
            counter = 0;
        }
    }
}
"""
    (main,) = parse_ok(text).items
    loop = main.body.items[-1]
    assert sx(loop.body.items[2].expr) == (
        "(= cnt_reach_delay_1s (call TON (& timer1) (>= counter target_cnt) 1000))"
    )


def test_manual_example_22_3_bit_macros():
    text = """
#define BIT_SET(a, idx)      ((a) |= (1<<(idx)))
#define BIT_CLEAR(a, idx)   ((a) &= ~(1<<(idx)))
#define BIT_FLIP(a, idx)    ((a) ^= (1<<(idx)))
#define BIT_CHECK(a, idx)   ((a) & (1<<(idx)))

void main() {
    int bits_value = 0;

    BIT_SET(bits_value, 0); // 此時 bits_value 的值為 1
    BIT_CLEAR(bits_value, 0); // 此時 bits_value 的值為 8
    BIT_FLIP(bits_value, 4); // 此時 bits_value 的值為 24

    bits_value = 684;
    if (BIT_CHECK(bits_value, 5)) {
        Print("bit 5 is 1");
    } else {
        Print("bit 5 is 0");
    }
}
"""
    (main,) = parse_ok(text).items
    items = main.body.items
    assert sx(items[1].expr) == "(|= bits_value (<< 1 0))"
    assert sx(items[2].expr) == "(&= bits_value (~ (<< 1 0)))"
    assert sx(items[5].cond) == "(& bits_value (<< 1 5))"
    assert items[1].expr.pos.line == 10  # the macro's use


def test_manual_example_1_5_scopes():
    text = """
int task_var = 0;

void TaskFunction1() {
    int local_var = task_var;
    for (int i = 0; i < local_var; ++i) { // 區塊開始
        global_var += i; // i 為具有區塊可視範圍的區域變數
    } // 區塊結束
    global_var += local_var;
}

void main() {
    task_var = 10;
    TaskFunction1();
    GlobalFunction1(); // 輸出為 155
}
"""
    tu = parse_ok(text, task_id=1)
    assert [type(x).__name__ for x in tu.items] == ["VarDecl", "FuncDef", "FuncDef"]


# ---------------------------------------------------------------- dumps


def test_dump_tokens_is_readable_and_deterministic():
    sink = DiagnosticSink()
    toks = preprocess("d.hmpl", task_id=0, sink=sink, text='int x = 0x10u; "s" 1.5f')
    assert dump_tokens(toks) == (
        "# file: d.hmpl\n"
        "1:1\tkeyword\tint\n"
        "1:5\tname\tx\n"
        "1:7\tpunct\t=\n"
        "1:9\tint\t0x10u\t16\tsuffix=u\n"
        "1:14\tpunct\t;\n"
        "1:16\tstring\t\"s\"\tb's'\n"
        "1:20\tfloat\t1.5f\t1.5\tsuffix=f\n"
        "1:24\teof\t\n"
    )


def test_dump_ast_is_readable_and_deterministic():
    tu = parse_ok("_AUTORUN_ void main() {\n  int a[2] = {1, 2};\n  a[0] += -1;\n}")
    assert (
        dump_ast(tu)
        == """\
TranslationUnit @1:1
  items:
    FuncDef @1:16 name='main' body=... autorun=True
""".replace(" body=...", "")
        + """\
      ret: TypeRef @1:11 base='void'
      body: Block @1:23
        items:
          DeclStmt @2:3
            decls:
              VarDecl @2:7 name='a'
                type: TypeRef @2:3 base='int32_t'
                dims:
                  IntLit @2:9 value=2
                init: InitList @2:14
                  items:
                    IntLit @2:15 value=1
                    IntLit @2:18 value=2
          ExprStmt @3:3
            expr: Assign @3:8 op='+='
              target: Index @3:4
                base: Name @3:3 id='a'
                index: IntLit @3:5 value=0
              value: Unary @3:11 op='-'
                operand: IntLit @3:12 value=1
"""
    )


def test_designated_initializers():
    tu = parse_ok(
        "typedef struct { double x, y; int f[3]; } P;\n"
        "P p = {.y = 5, .x = 1.5, .f = {1, 2}};\n"
        "int a[] = {[4] = 1, 2, [1] = 3};\n"
        "int b[] = {[N] = 1};\n"
        "P ps[2] = {[1] = {.x = 2}, {0}};\n"
    )
    _, p, a, b, ps = tu.items
    d0, d1, d2 = p.init.items
    assert (d0.field, d0.index, sx(d0.value)) == ("y", None, "5")
    assert (d1.field, sx(d1.value)) == ("x", "1.5")
    assert d2.field == "f" and isinstance(d2.value, n.InitList)
    assert [(x.field, sx(x.index)) for x in a.init.items if isinstance(x, n.Designated)] == [
        (None, "4"),
        (None, "1"),
    ]
    assert sx(a.dims[0]) == "6"  # [4], then [5], then [1]: six elements
    assert b.dims == (None,)  # a non-literal index: the checker sizes it
    first = ps.init.items[0]
    assert isinstance(first, n.Designated) and isinstance(first.value, n.InitList)
    assert first.value.items[0].field == "x"


def test_enums_become_integer_constants():
    tu = parse_ok(
        "enum Mode { IDLE, RUN = 5, STOP, LAST = RUN * 2 + 'a' - 97, NEG = -1, };\n"
        "enum Mode m = STOP;\n"
        "enum { A = 1 << 3, B = (int)A | 1, C = A > 4 ? 10 : 20 } e;\n"
        "int v[LAST];\n"
        "void f(enum Mode mode) { switch (mode) { case RUN: x = C + B; } }\n"
    )
    m, e, v, f = tu.items
    assert (m.type.base, sx(m.init)) == ("int32_t", "6")
    assert e.type.base == "int32_t"
    assert sx(v.dims[0]) == "10"
    assert f.params[0].type.base == "int32_t"
    case, assign = f.body.items[0].body.items
    assert sx(case.value) == "5"
    assert sx(assign.expr) == "(= x (+ 10 9))"


def test_every_parse_method_has_a_bnf_line():
    import inspect
    import re

    from motionvm.lang.hmpl import parser

    lines = inspect.getsource(parser).splitlines()
    methods = [k for k, line in enumerate(lines) if re.match(r"\s+def _parse_\w+\(", line)]
    assert len(methods) > 30
    for k in methods:
        assert lines[k - 1].strip().startswith("# BNF:"), lines[k]
