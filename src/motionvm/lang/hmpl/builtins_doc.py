"""Generate docs/lang/hmpl-builtins.md, the reference of every HMPL built-in, from the
package's catalogue (`data/hmpl_api.json`) and the built-ins motionvm implements.
`python -m motionvm.lang.hmpl.builtins_doc` rewrites the file (run from the repository
root); a test checks that it is current."""

from __future__ import annotations

import json
import re
from importlib import resources
from pathlib import Path

from motionvm.lang.hmpl.catalog import builtin_signatures
from motionvm.lang.hmpl.lib import implemented_names

DOC = Path("docs/lang/hmpl-builtins.md")

# Names the compiler itself handles (macros, Till), so no library method implements them.

HEADER = """# HMPL built-ins

Generated from the package's catalogue of the manual's built-ins
(`src/motionvm/data/hmpl_api.json`) by `python -m motionvm.lang.hmpl.builtins_doc`; do not
edit by hand. `motionvm builtins` lists the same functions on the command line.

{done} of {total} built-ins are implemented. A program may call any of them: every call is
type-checked against the manual's prototype, and a call of one that is not implemented
draws a compiler warning and, when the task reaches it, stops that task with
`runtime error in task N at t=S s: NAME is not implemented yet`.

Units follow the manual: positions in mm or deg, velocities in mm/s or deg/s, times given
by the program in ms; the unit column is empty where the manual gives none. Parameters
marked `out` are pointers through which the function writes its results. Sections are
those of the HIMC HMPL manual; "since" names the iA Studio version that introduced the
function.

| Chapter | Built-ins | Implemented |
|---|---|---|
"""


def _entries() -> list[dict]:
    text = resources.files("motionvm.data").joinpath("hmpl_api.json").read_text("utf-8")
    return json.loads(text)


def _md(text: str) -> str:
    """`text` as Markdown prose: no emphasis from `*` or a word's edge `_`, no table break."""
    text = text.replace("\\", "\\\\").replace("*", "\\*").replace("|", "\\|")
    text = re.sub(r"(?<![A-Za-z0-9])_|_(?![A-Za-z0-9])", r"\\_", text)
    return text.replace("<", "\\<")


def _anchor(title: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to '-'."""
    return re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-")


def _chapter_title(e: dict) -> str:
    return f"{e['section'].split('.')[0]} {e['chapter']}"


def _returns(e: dict) -> str:
    desc = e["returns_desc"]
    if e["returns"] == "void":
        return "**Returns** nothing (`void`)."
    if e["returns"] is None:
        return f"**Value**: {_md(desc)}" if desc else ""
    return f"**Returns** `{e['returns']}`: {_md(desc)}"


def _params(e: dict) -> list[str]:
    if not e["params"]:
        return ["No parameters."]
    out = ["| Parameter | Type | In/out | Unit | Meaning |", "|---|---|---|---|---|"]
    for p in e["params"]:
        typ = p["type"].replace("|", "\\|")
        unit = _md(p["unit"] or "")
        out.append(f"| `{p['name']}` | `{typ}` | {p['dir']} | {unit} | {_md(p['desc'])} |")
    return out


def _builtin(e: dict, prototype: str, implemented: bool) -> list[str]:
    out = [f"### `{e['name']}`", "", _md(e["purpose"]), "", "```c", prototype, "```", ""]
    out += _params(e) + [""]
    returns = _returns(e)
    if returns:
        out += [returns, ""]
    if e["remarks"]:
        out += ["Remarks:", ""] + [f"- {_md(r)}" for r in e["remarks"]] + [""]
    status = "implemented" if implemented else "not implemented yet"
    out += [f"Manual section {e['section']}, since {e['min_version']}. motionvm: {status}.", ""]
    return out


def render() -> str:
    """The whole reference: a chapter table, then each chapter's index and its built-ins."""
    sigs = builtin_signatures()
    impl = implemented_names()
    chapters: dict[str, list[dict]] = {}
    for e in sorted(_entries(), key=lambda e: [int(n) for n in e["section"].split(".")]):
        chapters.setdefault(_chapter_title(e), []).append(e)
    done = sum(e["name"] in impl for es in chapters.values() for e in es)
    total = sum(len(es) for es in chapters.values())
    out = [HEADER.format(done=done, total=total).rstrip("\n")]
    for title, es in chapters.items():
        n_impl = sum(e["name"] in impl for e in es)
        out.append(f"| [{title}](#{_anchor(title)}) | {len(es)} | {n_impl} |")
    out.append("")
    for title, es in chapters.items():
        out += [f"## {title}", "", "| Built-in | Section | Implemented | Purpose |"]
        out.append("|---|---|---|---|")
        for e in es:
            mark = "yes" if e["name"] in impl else "no"
            link = f"[`{e['name']}`](#{_anchor(e['name'])})"
            out.append(f"| {link} | {e['section']} | {mark} | {_md(e['purpose'])} |")
        out.append("")
        for e in es:
            out += _builtin(e, sigs[e["name"]].prototype, e["name"] in impl)
    return "\n".join(out).rstrip("\n") + "\n"


if __name__ == "__main__":
    DOC.parent.mkdir(parents=True, exist_ok=True)
    DOC.write_text(render(), encoding="utf-8")
