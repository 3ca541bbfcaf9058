"""docs/lang/hmpl-builtins.md is generated from the built-in catalogue and must be current."""

from pathlib import Path

from motionvm.lang.hmpl.builtins_doc import implemented_names, render
from motionvm.lang.hmpl.catalog import builtin_signatures

DOC = Path(__file__).resolve().parents[3] / "docs" / "lang" / "hmpl-builtins.md"


def test_builtins_doc_is_current():
    assert DOC.read_text(encoding="utf-8") == render(), (
        "run: python -m motionvm.lang.hmpl.builtins_doc"
    )


def test_every_builtin_has_a_section_with_its_prototype():
    text = render()
    for name, sig in builtin_signatures().items():
        assert f"### `{name}`\n" in text, name
        assert f"```c\n{sig.prototype}\n```" in text, name


def test_a_builtin_shows_units_return_value_and_state():
    text = render()
    move_abs = text.split("### `MoveAbs`\n")[1].split("\n### ")[0]
    assert "| `pos` | `double` | in | mm or deg | Absolute target position. |" in move_abs
    assert "**Returns** `int`: 0 on success" in move_abs
    assert "Manual section 5.2.4" in move_abs
    assert "motionvm: implemented." in move_abs
    assert {"Till", "_TASKID_", "MoveAbs"} <= implemented_names()


def test_the_count_matches_the_implemented_set():
    names = builtin_signatures()
    done = sum(n in implemented_names() for n in names)
    assert f"{done} of {len(names)} built-ins are implemented." in render()
