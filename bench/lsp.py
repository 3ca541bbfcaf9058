"""Benchmark: the language server on 5,000-line HMPL files.

- diagnostics: CPU time from an edit (a changed line) to the diagnostics ready to send
  (checked as `motionvm check` does, converted and serialized to JSON), in-process;
- hover and completion: CPU time of one request on an unchanged document, answer
  serialized, in-process (the document's index made once per version, before);
- index: CPU time of building a document's index (every name resolved to its declaration,
  what hover, completion, definition and rename read) of a 5,000- and a 20,000-line file:
  about four times as long for four times the lines;
- memory: resident size of a real `motionvm lsp` subprocess with 20 different 5,000-line
  files open, each hovered once (so each has its index), after their diagnostics came.
Every time is `time.process_time`, the median of REPEAT runs after a warm-up; the
diagnostics, hover and completion runs are interleaved, so load on a shared machine slows
all alike. Prints `RESULT name=value` lines.
Run: python bench/lsp.py
"""

from __future__ import annotations

import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

from lsprotocol import types as t
from pygls.protocol import default_converter

from motionvm.lsp.features import Features

REPEAT = 9  # odd: the median is one of the runs
LINES = 5000
FILES = 20
CONVERTER = default_converter()


def program(seed: int = 0, lines: int = LINES) -> str:
    """An HMPL program of `lines` lines: macros, a struct, globals, and functions with
    comments, loops, conditions, calls of built-ins and of each other."""
    out = [
        f"// generated program {seed}: a benchmark of the language server",
        "#define AXES 4",
        "#define LIMIT 1000",
        "struct Move { int axis; double pos; double vel; };",
        "struct Move moves[16];",
        "int done_count = 0;",
        "",
    ]
    i = 0
    while len(out) < lines - 12:
        out += [
            f"// step {i}: move axis {i % 4} and count what happened",
            f"int step_{seed}_{i}(int axis, double target) {{",
            "    int ret = 0;",
            "    double where = 0.0;",
            "    for (int k = 0; k < AXES; k++) {",
            "        if (k == axis) {",
            "            ret = MoveAbs(k, target + k);",
            "        } else {",
            "            where = where + moves[k].pos;",
            "        }",
            "    }",
            f'    if (ret != 0) Print("step {i}: error %d", ret);',
            "    done_count++;",
            f"    return ret + (int)where + {i % 7};",
            "}",
            "",
        ]
        i += 1
    calls = "".join(f"    step_{seed}_{k}(0, 1.0);\n" for k in range(min(i, 5)))
    body = "\n".join(out) + "\nvoid main() {\n" + calls + "}\n"
    return body


def serialized(value) -> int:
    return len(json.dumps(CONVERTER.unstructure(value)))


def in_process() -> tuple[float, float, float]:
    """(diagnostics after an edit, hover, completion) medians [s]."""
    sent: list[int] = []
    features = Features(lambda params: sent.append(serialized(params)))
    folder = Path(tempfile.mkdtemp())
    path = folder / "big.hmpl"
    text = program()
    path.write_text(text)
    uri = path.resolve().as_uri()
    features.opened(uri, "hmpl", text, 1)
    lines = text.split("\n")
    row = next(k for k, line in enumerate(lines) if "done_count++" in line)
    hover = t.HoverParams(t.TextDocumentIdentifier(uri), t.Position(row - 6, 20))
    completion = t.CompletionParams(t.TextDocumentIdentifier(uri), t.Position(row, 4))

    def edit(version: int) -> float:
        lines[row] = f"    done_count += {version};"
        changed = "\n".join(lines)
        t0 = time.process_time()
        features.changed(uri, changed, version)
        return time.process_time() - t0

    def ask(method, params) -> float:
        t0 = time.process_time()
        serialized(method(params))
        return time.process_time() - t0

    edit(2)
    features.docs[uri].index  # noqa: B018 — made once per version, as the server does
    ask(features.hover, hover), ask(features.completion, completion)  # warm-up
    d_all, h_all, c_all = [], [], []
    for k in range(REPEAT):
        d_all.append(edit(3 + k))
        features.docs[uri].index  # noqa: B018
        h_all.append(ask(features.hover, hover))
        c_all.append(ask(features.completion, completion))
    assert features.hover(hover) is not None
    assert sent, "diagnostics were published"
    return statistics.median(d_all), statistics.median(h_all), statistics.median(c_all)


def index_time(lines: int) -> float:
    """CPU seconds of indexing a `lines`-line program (median of 3 after a warm-up)."""
    from motionvm.lang.hmpl.language import LANGUAGE

    text = program(1, lines)
    times = []
    for _ in range(4):
        t0 = time.process_time()
        index = LANGUAGE.index("big.hmpl", text)
        times.append(time.process_time() - t0)
        assert index.occurrences
    return statistics.median(times[1:])


def server_memory() -> float:
    """Resident size [MB] of `motionvm lsp` with FILES files of LINES lines open."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "lsp"))
    from lsp_client import LspClient

    folder = Path(tempfile.mkdtemp())
    client = LspClient(cwd=folder)
    try:
        client.initialize()
        for k in range(FILES):
            path = folder / f"f{k}.hmpl"
            text = program(k)
            path.write_text(text)
            uri = path.resolve().as_uri()
            client.open(uri, text)
            client.diagnostics(uri, timeout=120)
            assert client.at("textDocument/hover", uri, 13, 20) is not None
        status = Path(f"/proc/{client.proc.pid}/status").read_text()
        kb = next(int(line.split()[1]) for line in status.splitlines() if line.startswith("VmRSS"))
    finally:
        client.close()
    return kb / 1024


def main() -> None:
    diag, hover, completion = in_process()
    print(f"diagnostics after an edit of a {LINES}-line file: {diag * 1e3:.0f} ms (median)")
    print(f"hover: {hover * 1e3:.1f} ms, completion: {completion * 1e3:.1f} ms (medians)")
    small, large = index_time(LINES), index_time(4 * LINES)
    print(f"index of a {LINES}-line file: {small * 1e3:.0f} ms, of {4 * LINES} lines: "
          f"{large * 1e3:.0f} ms")  # fmt: skip
    rss = server_memory()
    print(f"server with {FILES} open {LINES}-line files: {rss:.0f} MB resident")
    print(f"RESULT lsp_diagnostics_ms={diag * 1e3:.1f}")
    print(f"RESULT lsp_hover_ms={hover * 1e3:.2f}")
    print(f"RESULT lsp_completion_ms={completion * 1e3:.2f}")
    print(f"RESULT lsp_index_ms={small * 1e3:.0f}")
    print(f"RESULT lsp_index_4x_lines_ms={large * 1e3:.0f}")
    print(f"RESULT lsp_memory_20_files_mb={rss:.0f}")


if __name__ == "__main__":
    main()
