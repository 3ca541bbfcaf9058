"""Constant expressions outside the compiler proper: `#if` and enumerator values follow
the run-time shift rule (a negative count is an error, a count past the width is taken
modulo it); a macro expansion over its budget is one error, not two."""

from __future__ import annotations


def test_if_with_a_negative_shift_count_is_an_error(cli):
    r = cli("check", "a.hmpl", a__hmpl="#if 1 << -1\nint x;\n#endif\nvoid main() { }\n")
    assert r.code == 2
    assert r.stderr.splitlines()[0] == "a.hmpl:1:7: error: negative shift count -1 in #if"


def test_if_shift_counts_past_the_width_wrap(cli):
    text = '#if (1 << 65) == 2 && (8 >> 66) == 2\nint ok = 1;\n#endif\nvoid main() { Print("%d", ok); }\n'
    r = cli("run", "a.hmpl", a__hmpl=text)
    assert (r.code, r.stdout) == (0, "1\n")


def test_enumerator_values_are_checked_one_error_each(cli):
    text = (
        "enum { A = 1 << 40, B = 1 << -2, C = 1 << 64, D = 5 / 0, E = 1 << 30, F = -8 >> 1 };\n"
        'void main() { Print("%d %d", E, F); }\n'
    )
    r = cli("check", "a.hmpl", a__hmpl=text)
    assert r.code == 2
    assert [x for x in r.stderr.splitlines() if "error:" in x] == [
        "a.hmpl:1:8: error: enumerator value 1099511627776 of 'A' is outside the range of int"
        " [-2147483648, 2147483647]",
        "a.hmpl:1:27: error: negative shift count -2 in the value of enumerator 'B'",
        "a.hmpl:1:34: error: enumerator value 18446744073709551616 of 'C' is outside the range"
        " of int [-2147483648, 2147483647]",
        "a.hmpl:1:53: error: division by zero in the value of enumerator 'D'",
    ]
    ok = text.replace("A = 1 << 40, B = 1 << -2, C = 1 << 64, D = 5 / 0, ", "")
    r = cli("run", "a.hmpl", a__hmpl=ok)
    assert (r.code, r.stdout) == (0, "1073741824 -4\n")


def test_a_macro_over_its_budget_is_one_error(cli):
    lines = ["#define A0(x) x x"] + [f"#define A{i}(x) A{i - 1}(A{i - 1}(x))" for i in range(1, 40)]
    lines.append('void main(void) { int y = A39(1); Print("%d", y); }')
    r = cli("check", "a.hmpl", a__hmpl="\n".join(lines) + "\n")
    assert r.code == 2
    assert [x for x in r.stderr.splitlines() if "error:" in x] == [
        "a.hmpl:41:27: error: macro expansion of 'A39' produces more than 1000000 tokens"
    ]
