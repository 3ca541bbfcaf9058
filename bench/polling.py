"""Benchmark: a scan loop that polls inputs (the manual's edge detector, 9.1.2), against
the same loop kept spinning.

The program: `while (1) { in = GetGPI(4); if (in ^ last) { ...; Print(...); } last = in; }`
with a scenario toggling input 4 every 100 ms. The loop ends its slice at the first
iteration that changes nothing, and its quiet iterations read only an input, so with
skipping on the clock jumps from toggle to toggle. The reference loops on a call of the
program's own function (`while (yes())`), which keeps the spin of any other loop: every
cycle runs the task's whole slice (2000 iterations), as every loop did before. Both
print the same lines (asserted).

Prints `RESULT polling_loop_realtime_factor` (skipping), `..._stepped_realtime_factor`
(skipping off) and `polling_loop_spin_realtime_factor` (the spinning reference,
stepped). Timing: CPU seconds of `Simulation.run()` (`time.process_time`), the median
of 5 repeats after a warm-up round, the cases interleaved.
Run: python bench/polling.py [--seconds S] [--repeat R]
"""

from __future__ import annotations

import argparse
import statistics
import time

from motionvm.api import Simulation

PROGRAM = """
int yes() { return 1; }
void main() {
    int last = 0, edges = 0;
    while (FOREVER) {
        int in = GetGPI(4);
        if ((in ^ last) && in) {
            edges++;
            SetGPO(3, edges & 1);
            Print("edge %d at %d ms: output 3 %d", edges, system_timeInMs, GetGPO(3));
        }
        last = in;
    }
}
"""
TOGGLE_S = 0.1


def run_once(forever: str, skip: bool, seconds: float) -> tuple[float, list[str]]:
    sim = Simulation.from_source(PROGRAM.replace("FOREVER", forever), skip=skip)
    t_cpu = 0.0
    on = False
    t = 0.0
    while t < seconds:  # the scenario: input 4 toggles every TOGGLE_S
        t = min(seconds, t + TOGGLE_S)
        t_0 = time.process_time()
        sim.run(until=t)
        t_cpu += time.process_time() - t_0
        on = not on
        sim.set_input(4, on)
    return t_cpu, sim.messages


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=2.0, help="simulated seconds per run")
    ap.add_argument("--repeat", type=int, default=5, help="timed repeats per case (median)")
    args = ap.parse_args()
    cases = {"skip": ("1", True), "stepped": ("1", False), "spin": ("yes()", False)}
    times: dict[str, list[float]] = {c: [] for c in cases}
    outputs: dict[str, list[str]] = {}
    for k in range(args.repeat + 1):  # the first round warms up, untimed
        for case, (forever, skip) in cases.items():
            cpu, messages = run_once(forever, skip, args.seconds)
            if outputs.setdefault(case, messages) != messages:
                raise SystemExit(f"benchmark broken: runs of case {case} printed differently")
            if k:
                times[case].append(args.seconds / cpu)
    if not outputs["skip"] == outputs["stepped"] == outputs["spin"]:
        raise SystemExit("benchmark broken: the polling loop and its spin printed differently")
    factor = {case: statistics.median(v) for case, v in times.items()}
    print(f"scan loop, {args.seconds} s: {factor['skip']:.1f}x real time skipping, "
          f"{factor['stepped']:.1f}x stepping, {factor['spin']:.2f}x spinning")  # fmt: skip
    print(f"RESULT polling_loop_realtime_factor={factor['skip']:.1f}")
    print(f"RESULT polling_loop_stepped_realtime_factor={factor['stepped']:.1f}")
    print(f"RESULT polling_loop_spin_realtime_factor={factor['spin']:.2f}")


if __name__ == "__main__":
    main()
