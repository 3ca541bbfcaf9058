"""PDO mapping entries of a machine file's `drive = { rxpdo, txpdo }` are ASCII numbers:
anything else is exit 3 naming the entry (digits of other scripts and decimal numbers
with leading zeros used to escape as Python's own int() messages, without a location)."""

from __future__ import annotations

import pytest

PROGRAM = 'void main() { Print("ok"); }\n'


def run(cli, drive: str):
    return cli(
        "run", "--until", "0.01", "--machine", "m.toml", "a.hmpl",
        m__toml=f"[[axis]]\ndrive = {{ {drive} }}\n", a__hmpl=PROGRAM,
    )  # fmt: skip


@pytest.mark.parametrize(
    "entry",
    ["0\u0663", "\u0660x6040", "0x6060:\u0661", "0x6060:" + "0" * 40, "9" * 5000, "0x" + "f" * 40],
)
def test_an_entry_that_is_no_ascii_number_is_exit_3_naming_it(cli, entry):
    r = run(cli, f'rxpdo = [0x6040, 0x607A, "{entry}"]')
    assert r.code == 3, r.stderr
    first = r.stderr.splitlines()[0]
    assert first.startswith("m.toml:2:11: error: [[axis]] 0: drive: rxpdo = "), first
    assert "is not an object index" in first or "is out of range" in first, first


@pytest.mark.parametrize("entry", ["0x6060:00", "0x60FE:01", "24672:0", " 0x6060 : 0 "])
def test_decimal_subindexes_with_leading_zeros_are_numbers(cli, entry):
    r = run(cli, f'rxpdo = [0x6040, 0x607A, "{entry}"]')
    assert (r.code, r.stdout) == (0, "ok\n"), r.stderr


def test_a_subindex_with_leading_zeros_names_the_object_it_means(cli):
    r = run(cli, 'rxpdo = [0x6040, 0x607A, "0x6060:08"]')
    assert r.code == 3
    assert "object 0x6060:8 does not exist" in r.stderr.splitlines()[0]
