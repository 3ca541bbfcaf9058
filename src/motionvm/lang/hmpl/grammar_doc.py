"""Generate docs/lang/hmpl.md from the `# BNF:` lines of the HMPL parser (the grammar is the
documentation). `python -m motionvm.lang.hmpl.grammar_doc` rewrites the file
(run from the repository root); a test checks that it is current."""

from __future__ import annotations

import re
from pathlib import Path

PARSER = Path(__file__).with_name("parser.py")
DOC = Path("docs/lang/hmpl.md")

HEADER = """# HMPL grammar

Generated from the `# BNF:` comments of `src/motionvm/lang/hmpl/parser.py` by
`python -m motionvm.lang.hmpl.grammar_doc`; do not edit by hand. Notation: `{ x }` repeats,
`[ x ]` is optional, `|` separates alternatives, quoted text is literal. The preprocessor
(`#define`, `#if`, `#include`, `#line`, `_TASKID_`) runs before this grammar.

```ebnf
"""


def grammar_lines(source: str) -> list[str]:
    """The BNF comment lines in parser order, continuation lines kept indented."""
    out = []
    for line in source.splitlines():
        m = re.match(r"\s*# BNF:(.*)$", line)
        if m:
            text = m.group(1)
            out.append(
                text[1:]
                if text.startswith(" ") and not text.startswith("     ")
                else "    " + text.strip()
            )
    return out


def render(source: str) -> str:
    return HEADER + "\n".join(grammar_lines(source)) + "\n```\n"


if __name__ == "__main__":
    DOC.parent.mkdir(parents=True, exist_ok=True)
    DOC.write_text(render(PARSER.read_text(encoding="utf-8")), encoding="utf-8")
