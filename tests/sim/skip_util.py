"""What the random skip-against-step tests share: a machine file from drawn axis tables,
and the outcome of one run of a set of task sources (with skipping or stepping), every
field compared between the two."""

from __future__ import annotations

from motionvm.api import Simulation


def machine_file(tmp_path, spec, n_axes: int) -> str:
    """A machine file for `spec` = (cycle time [ms], one axis table per axis; each table's
    `delay` is the ideal drive's delay in cycles, the rest go to `[[axis]]` as they are)."""
    cycle_ms, axes = spec
    lines = [f"axes = {n_axes}", "[controller]", f"cycle_time_ms = {cycle_ms}"]
    for ax in axes:
        lines += ["[[axis]]"] + [f"{k} = {v}" for k, v in ax.items() if k != "delay"]
        lines.append(
            f'drive = {{ mechanics = {{ model = "ideal", delay_cycles = {ax["delay"]} }} }}'
        )
    path = tmp_path / "machine.toml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def outcome(tmp_path, sources: list[str], skip: bool, machine: str | None = None,
            timeout: float = 60.0) -> tuple:  # fmt: skip
    """(run result, messages, simulated time, every axis's state) of the sources run."""
    sim = Simulation.from_files(
        task_files(tmp_path, sources), skip=skip, stamp=True, machine=machine
    )
    result = sim.run(timeout=timeout)
    return str(result), list(sim.messages), sim.time, axis_states(sim)


def task_files(tmp_path, sources: list[str]) -> list:
    """The task sources written as t0.hmpl, t1.hmpl, ... in `tmp_path`: their paths."""
    paths = []
    for i, text in enumerate(sources):
        p = tmp_path / f"t{i}.hmpl"
        p.write_text(text, encoding="utf-8")
        paths.append(p)
    return paths


def axis_states(sim: Simulation) -> list[tuple]:
    """What the random tests compare of every axis after a run."""
    return [(a.pos_fb, a.ref_pos, a.ref_vel, a.ref_acc, a.in_pos, a.moving, a.move_time_ms,
             a.settling_time_ms, a.last_error, a.resting, a.drive.position_actual,
             a.drive.digital_inputs, a.drive.mechanics.velocity, a.drive.mechanics.torque)
            for a in sim.controller.motion.axes]  # fmt: skip
