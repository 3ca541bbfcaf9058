"""The preprocessor's expansion budget: memory stays bounded, the error is clear."""

import subprocess
import sys

from motionvm.lang.hmpl.preprocess import MAX_TOKENS, preprocess
from motionvm.source.diagnostics import DiagnosticSink


def _doubling(levels: int) -> str:
    lines = ["#define A0(x) x x"]
    lines += [f"#define A{i}(x) A{i - 1}(A{i - 1}(x))" for i in range(1, levels + 1)]
    lines.append(f"void main(void) {{ int y = A{levels}(1); }}")
    return "\n".join(lines) + "\n"


def test_doubling_macros_stop_at_the_token_budget_with_bounded_memory():
    # in a child process, whose peak resident size is the bound (tracemalloc would
    # measure the same but run the expansion some 30 times slower)
    probe = (
        "import sys\n"
        "from motionvm.lang.hmpl.preprocess import preprocess\n"
        "from motionvm.source.diagnostics import DiagnosticSink\n"
        "sink = DiagnosticSink()\n"
        "preprocess('blow.hmpl', task_id=0, sink=sink, text=sys.stdin.read())\n"
        # the peak of this process's own memory: VmHWM (getrusage's ru_maxrss would count
        # the pages of the parent it was forked from, a large pytest process)
        "print(next(line.split()[1] for line in open('/proc/self/status')\n"
        "           if line.startswith('VmHWM:')))\n"
        "for d in sink.items: print(d.headline())\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], input=_doubling(39), capture_output=True, text=True,
        timeout=300, check=True,
    )  # fmt: skip
    peak_kb, *headlines = done.stdout.splitlines()
    assert headlines == [
        f"blow.hmpl:41:27: error: macro expansion of 'A39' produces more than {MAX_TOKENS} tokens"
    ]
    assert int(peak_kb) < 400_000, peak_kb  # KB: interpreter and imports included


def test_budget_is_per_file_not_per_region():
    # each region stays under the budget; together they pass it
    big = "#define T10 x x x x x x x x x x\n#define T100 T10 T10 T10 T10 T10 T10 T10 T10 T10 T10\n"
    big += "#define T1K T100 T100 T100 T100 T100 T100 T100 T100 T100 T100\n"
    big += "#define T10K T1K T1K T1K T1K T1K T1K T1K T1K T1K T1K\n"
    big += "#define T100K T10K T10K T10K T10K T10K T10K T10K T10K T10K T10K\n"
    text = big + "".join(f"T100K\n#define D{k}\n" for k in range(12))
    sink = DiagnosticSink()
    preprocess("many.hmpl", task_id=0, sink=sink, text=text)
    errors = [d.headline() for d in sink.errors()]
    assert len(errors) == 1 and errors[0].endswith(
        f"macro expansion of 'T100K' produces more than {MAX_TOKENS} tokens"
    )


def test_ordinary_expansion_is_untouched():
    sink = DiagnosticSink()
    toks = preprocess("ok.hmpl", task_id=0, sink=sink, text=_doubling(3))
    assert not sink.items
    assert sum(t.text == "1" for t in toks) == 256
