"""The command line's grammar: subcommands and options of `motionvm` (argparse)."""

from __future__ import annotations

import argparse


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="motionvm", description="A virtual motion controller for HMPL, PDL and GDL programs."
    )
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="compile and run programs on the simulated machine")
    r.add_argument("files", nargs="*", metavar="FILE")
    r.add_argument(
        "--machine", metavar="FILE.toml", help="machine file (default: the built-in machine)"
    )
    r.add_argument(
        "--until",
        type=float,
        metavar="SECONDS",
        help="run this long (simulated time); exit 0, with a note of what still ran",
    )
    r.add_argument(
        "--timeout",
        type=float,
        metavar="SECONDS",
        help="a run that has not finished after this much simulated time fails (exit 124), "
        "naming where each task waits",
    )
    r.add_argument("--stamp", action="store_true", help="prefix messages with [t=SECONDS][task N]")
    r.add_argument(
        "--task", action="append", default=[], metavar="N=FILE", help="put FILE on task N"
    )
    r.add_argument("--realtime", action="store_true", help="pace the simulation to the wall clock")
    r.add_argument(
        "--no-skip",
        action="store_true",
        help="step every cycle instead of jumping over idle ones (same output, slower)",
    )
    _werror(r)
    r.add_argument("--scenario", metavar="FILE.toml", help="GDL: timed input changes")
    r.add_argument(
        "--scope",
        action="append",
        default=[],
        metavar="CH,CH,...",
        help="record channels each cycle: axis0.ref_pos, system_dtest0, gpo3, a global ...",
    )
    r.add_argument(
        "--scope-out",
        action="append",
        default=[],
        metavar="FILE",
        help="write the recording to FILE: .csv, .png, .svg or .vcd, or - for a .csv table on "
        "stdout after the run's messages (repeatable)",
    )
    r.add_argument("--scope-every", type=int, metavar="N", help="record every N cycles (default 1)")
    r.add_argument(
        "--scope-window",
        metavar="START:END",
        help="write only the samples from START to END seconds (either may be empty; 150ms)",
    )
    r.add_argument(
        "--start",
        action="append",
        default=[],
        metavar="LABEL",
        help="PDL: start a task at this label ('top' = the first statement); repeatable",
    )
    r.add_argument(
        "--force",
        action="append",
        default=[],
        metavar="'REF = V'",
        help="GDL: force a state variable with f access (repeatable)",
    )
    r.add_argument(
        "--shuffle-order",
        type=int,
        metavar="SEED",
        help="GDL: permute the order of procedures sharing an activator",
    )
    c = sub.add_parser("check", help="compile only; report errors")
    c.add_argument("files", nargs="+", metavar="FILE")
    c.add_argument("--task", action="append", default=[], metavar="N=FILE")
    _werror(c)
    k = sub.add_parser("compile", help="compile and show the generated Python")
    k.add_argument("files", nargs="+", metavar="FILE")
    k.add_argument("--emit-python", action="store_true", help="print the generated Python code")
    k.add_argument("--task", action="append", default=[], metavar="N=FILE")
    _werror(k)
    b = sub.add_parser("builtins", help="list every HMPL built-in and whether it is implemented")
    b.add_argument("--json", action="store_true")
    d = sub.add_parser("dump", help="show a compiler stage")
    d.add_argument("--stage", choices=["tokens", "ast", "py"], required=True)
    d.add_argument("file", metavar="FILE")
    d.add_argument("--task-id", type=int, default=0)
    add_test_parser(sub)
    return p


def add_test_parser(sub) -> None:
    """`motionvm test`: run programs that carry expectations (see cli/cases.py)."""
    t = sub.add_parser("test", help="run programs that carry expectations; report like pytest")
    t.add_argument(
        "files", nargs="*", metavar="PATH", help="files or folders (default: the current folder)"
    )
    t.add_argument("-k", metavar="EXPR", help="only cases whose path contains EXPR ('not X' too)")
    t.add_argument("-x", "--exitfirst", action="store_true", help="stop at the first failure")
    t.add_argument("-q", "--quiet", action="count", default=0, help="less output")
    t.add_argument("-v", "--verbose", action="count", default=0, help="one line per case")
    t.add_argument(
        "-j", "--jobs", type=int, metavar="N", help="worker processes (default: one per CPU)"
    )
    t.add_argument(
        "--case-timeout",
        type=float,
        default=60.0,
        metavar="SECONDS",
        help="wall-clock time limit of one case (default 60)",
    )
    t.add_argument("--junitxml", metavar="FILE", help="also write a JUnit XML report")
    t.add_argument("--dask", metavar="ADDRESS", help="run the cases on the Dask cluster at ADDRESS")


def _werror(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--Werror", dest="werror", action="store_true", help="treat compiler warnings as errors"
    )
