"""`motionvm builtins [NAME] [--missing] [--chapter N]` and `motionvm errors [CODE]`."""

from __future__ import annotations

import json

import pytest


def test_builtins_name_describes_one(motionvm, tmp_path):
    r = motionvm("builtins", "MoveAbs", cwd=tmp_path)
    assert r.returncode == 0 and r.stderr == ""
    lines = r.stdout.splitlines()
    assert lines[0] == "MoveAbs  (manual 5.2.4, Axis functions): implemented"
    assert lines[1] == "  int MoveAbs(int axis_id, double pos);"
    assert "  Move an axis to an absolute target position." in lines
    assert "  pos      double  in   Absolute target position. Unit: mm or deg." in lines
    assert lines[lines.index("Returns: int") + 1] == "  0 on success; non-zero on failure."


def test_builtins_says_every_built_in_is_implemented(motionvm, tmp_path):
    r = motionvm("builtins", cwd=tmp_path)
    every = json.loads(motionvm("builtins", "--json", cwd=tmp_path).stdout)
    assert r.stdout.splitlines()[-1] == f"{len(every)} of {len(every)} built-ins implemented"
    assert all(row["implemented"] for row in every)


def test_builtins_name_json_has_the_manual_entry(motionvm, tmp_path):
    row = json.loads(motionvm("builtins", "SetVel", "--json", cwd=tmp_path).stdout)
    assert row["name"] == "SetVel" and row["implemented"] is True
    assert row["prototype"] == "int SetVel(int axis_id, double vel);"
    assert [p["unit"] for p in row["params"]] == [None, "mm/s or deg/s"]


@pytest.mark.parametrize(
    ("name", "hint"),
    [
        ("MovAbs", "did you mean MoveAbs,"),  # the closest first
        ("moveabs", "did you mean MoveAbs"),
        ("PI", "PI is a constant"),
    ],
)
def test_an_unknown_builtin_gets_a_did_you_mean_and_exit_3(motionvm, tmp_path, name, hint):
    r = motionvm("builtins", name, cwd=tmp_path)
    assert r.returncode == 3 and r.stdout == ""
    assert r.stderr.startswith(f"motionvm: error: no HMPL built-in is called '{name}'")
    assert hint in r.stderr


def test_builtins_missing_lists_only_the_unimplemented(motionvm, tmp_path):
    every = json.loads(motionvm("builtins", "--json", cwd=tmp_path).stdout)
    missing = json.loads(motionvm("builtins", "--missing", "--json", cwd=tmp_path).stdout)
    assert missing == [row for row in every if not row["implemented"]]
    r = motionvm("builtins", "--missing", cwd=tmp_path)
    lines = r.stdout.splitlines()
    assert [line.split()[0] for line in lines[:-1]] == [row["name"] for row in missing]
    assert all(line.split()[1] == "no" for line in lines[:-1])
    assert lines[-1] == f"{len(missing)} of {len(every)} built-ins not implemented"


def test_builtins_chapter_lists_one_chapter(motionvm, tmp_path):
    rows = json.loads(motionvm("builtins", "--chapter", "7", "--json", cwd=tmp_path).stdout)
    assert [r["name"] for r in rows] == [
        "EnableGantryPair",
        "DisableGantryPair",
        "GetGantryPairID",
        "IsGantryPair",
    ]
    assert {r["section"].split(".")[0] for r in rows} == {"7"}
    text = motionvm("builtins", "--chapter", "7", cwd=tmp_path).stdout.splitlines()
    assert text[-1] == "4 of 4 built-ins of chapter 7 (Gantry functions) implemented"
    r = motionvm("builtins", "--chapter", "1", cwd=tmp_path)
    assert r.returncode == 3 and "chapter 1 of the manual has no built-ins" in r.stderr


def test_builtins_json_keeps_its_fields(motionvm, tmp_path):
    rows = json.loads(motionvm("builtins", "--json", cwd=tmp_path).stdout)
    assert len(rows) == 324
    assert all({"name", "prototype", "implemented"} <= set(row) for row in rows)


# ------------------------------------------------------------------ errors


def test_errors_decodes_an_axis_code(motionvm, tmp_path):
    r = motionvm("errors", "0x83010136", cwd=tmp_path)
    assert r.returncode == 0 and r.stderr == ""
    assert r.stdout.splitlines() == [
        "0x83010136  eERR_AXIS_CMD_INVALID_POS  (axis 1)",
        "  The axis target position is outside the allowed range.",
        "  Manual 18.1.2, axis errors: 0x83XX0136, XX = the axis id in hex.",
        "  In decimal: 2197881142 (Print's %d shows -2097086154).",
    ]


@pytest.mark.parametrize("code", ["0x83000136", "2197815606", "-2097151690", "0X83000136"])
def test_errors_takes_hex_and_decimal(motionvm, tmp_path, code):
    r = motionvm("errors", code, cwd=tmp_path)
    assert r.returncode == 0
    assert r.stdout.startswith("0x83000136  eERR_AXIS_CMD_INVALID_POS  (axis 0)\n")


def test_errors_decodes_a_group_code_and_a_system_code(motionvm, tmp_path):
    r = motionvm("errors", "0x8203000a", cwd=tmp_path)
    assert r.stdout.startswith("0x8203000a  eERR_CRD_CMD_UNKNOWN  (group 3)\n")
    assert "Manual 18.1.3, group errors: 0x82XX000a" in r.stdout
    r = motionvm("errors", "100", cwd=tmp_path)
    assert r.stdout.splitlines()[:3] == [
        "0x00000064  eERR_EMERGENCY_STOP",
        "  The controller has been emergency-stopped.",
        "  Manual 18.1.1, system errors.",
    ]


def test_errors_takes_the_manuals_spelling_and_names(motionvm, tmp_path):
    for text in ("0x83XX0136", "eERR_AXIS_CMD_INVALID_POS"):
        r = motionvm("errors", text, cwd=tmp_path)
        assert r.stdout.startswith("0x83XX0136  eERR_AXIS_CMD_INVALID_POS\n")


@pytest.mark.parametrize(
    ("code", "words"),
    [
        ("0x12345678", "0x12345678 is not an error code of the manual's chapter 18"),
        ("0x8301abcd", "has the form of an axis error code (axis 1), but 0xabcd is not"),
        ("0x820200a0", "has the form of a group error code (group 2), but 0x00a0 is not"),
        ("eERR_AXIS_CMD_INVALID_PO", "did you mean eERR_AXIS_CMD_INVALID_POS"),
        ("0x1ffffffff", "is neither an error code"),
        # hex digits without 0x: read as decimal, with the code they spell in hex
        (
            "83010136",
            "0x04f2a258 is not an error code of the manual's chapter 18 (did you "
            "mean 0x83010136, in hex?)",
        ),
        ("83XX0136", "nor the name of one (did you mean 0x83XX0136, in hex?)"),
    ],
)
def test_an_unknown_code_says_so_exit_3(motionvm, tmp_path, code, words):
    r = motionvm("errors", code, cwd=tmp_path)
    assert r.returncode == 3 and r.stdout == ""
    assert r.stderr.startswith("motionvm: error: ") and words in r.stderr


def test_errors_without_a_code_lists_every_code(motionvm, tmp_path):
    lines = motionvm("errors", cwd=tmp_path).stdout.splitlines()
    assert len(lines) == 208
    assert lines[0].split()[:2] == ["0x00000001", "eERR_HCV_ID_NOT_FOUND"]
    assert any(line.split()[:2] == ["0x83XX0136", "eERR_AXIS_CMD_INVALID_POS"] for line in lines)


def test_builtins_takes_a_glob(motionvm, tmp_path):
    r = motionvm("builtins", "Move*", cwd=tmp_path)
    assert r.returncode == 0
    names = [line.split()[0] for line in r.stdout.splitlines()[:-1]]
    assert names and all(n.startswith("Move") for n in names)
    assert {"MoveAbs", "MoveRel", "MoveVel"} <= set(names)
    assert r.stdout.splitlines()[-1] == f"{len(names)} built-ins match 'Move*', the closest first"
    same = motionvm("builtins", "move*", "--json", cwd=tmp_path)
    assert [row["name"] for row in json.loads(same.stdout)] == names  # case-insensitive


def test_builtins_takes_a_search_word_closest_names_first(motionvm, tmp_path):
    r = motionvm("builtins", "home", cwd=tmp_path)
    assert r.returncode == 0
    names = [line.split()[0] for line in r.stdout.splitlines()[:-1]]
    assert {"MoveHome", "IsHomed", "SetHomeMethod"} <= set(names)
    by_name = [n for n in names if "home" in n.lower()]
    assert names[: len(by_name)] == by_name  # names that hold the word before purposes


def test_builtins_ranks_the_closest_names_first(motionvm, tmp_path):
    r = motionvm("builtins", "movabs", cwd=tmp_path)
    assert r.returncode == 3
    hint = r.stderr.split("did you mean ", 1)[1]
    assert hint.startswith("MoveAbs") and hint.index("MoveAbs") < hint.index("abs,")


def test_a_glob_that_finds_nothing_is_exit_3(motionvm, tmp_path):
    r = motionvm("builtins", "Zork*", cwd=tmp_path)
    assert r.returncode == 3 and r.stdout == ""
    assert r.stderr.startswith("motionvm: error: no HMPL built-in matches 'Zork*'")
