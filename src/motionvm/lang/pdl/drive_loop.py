"""The drive's phase loop: pick the task of each phase, resume it, step the axis.

Kept apart from `drive_rt.Drive` because it is the hot path of a simulation: one
iteration per 66.7 µs phase, locals only. Weighted round-robin as `drive_rt`
describes; a phase in which no task is runnable and the axis rests is skipped in one
jump to the next wake-up (identical to stepping: nothing else changes meanwhile).

A task's request, as it yields (lower_body):
    int r                 its budget ran out (r <= 0: overdraft -r statements, paid
                          by sitting out ceil(-r / budget) of its phases)
    (SLEEP, ms, b)        sleep; it is not runnable for ceil(ms * rate / 1000) phases
    (WAIT, units, b)      busy wait; it keeps its phases but does nothing in them
"""

from __future__ import annotations

from motionvm.lang.pdl.drive_sysvars import SYS_BASE
from motionvm.lang.pdl.drive_task import DriveState
from motionvm.lang.pdl.lower_body import SLEEP
from motionvm.lang.pdl.rt_memory import round_int
from motionvm.lang.pdl.sysvars import lookup
from motionvm.motion.profile import IDLE
from motionvm.runtime.errors import TaskExit

_WRAP = 1 << 32
_FCLK_MAX = (1 << 31) - 1


def run_phases(d: DriveState, count: int | None) -> bool:
    """Run up to `count` phases (None: until idle); True if every task ended and the axis rests."""
    cfg = d.config
    budget = cfg.budget
    rate = cfg.phase_rate
    wait_num = cfg.wait_unit_us * rate
    tasks = d.tasks
    n_tasks = len(tasks)
    store = d.sysvars
    S, ST = store.S, store.ST
    i_fclk, i_tnum, i_prior = SYS_BASE["fclk"], SYS_BASE["task_num"], SYS_BASE["task_prior"]
    i_xref, i_ref = SYS_BASE["x_ref_pos"], SYS_BASE["ref_pos"]
    b_run = lookup("x_run").address  # type: ignore[union-attr]
    axis = d.axis
    pg = axis.pg
    switches = cfg.axis.home_position is not None or cfg.axis.left_limit is not None
    ph = d.phase
    end = None if count is None else ph + count
    fclk = S[i_fclk]
    cur, left = d._cur, d._left
    done = False
    try:
        while end is None or ph < end:
            t = None
            owner = d.lock_owner
            if owner is not None:
                t = tasks[owner]
                if t.gen is None or t.wake > ph:
                    t = None
            else:
                t = tasks[cur]
                if left <= 0 or t.gen is None or t.wake > ph:
                    t = None
                    for k in range(1, n_tasks + 1):
                        c = cur + k
                        if c >= n_tasks:
                            c -= n_tasks
                        tk = tasks[c]
                        if tk.gen is not None and tk.wake <= ph:
                            t, cur = tk, c
                            p = S[i_prior + c]
                            left = max(1, p)
                            break
            if t is None:
                if pg.mode == IDLE:
                    if owner is not None and tasks[owner].gen is not None:
                        wakes = [tasks[owner].wake]
                    else:
                        wakes = [x.wake for x in tasks if x.gen is not None]
                    if not wakes:
                        done = True
                        break
                    target = min(wakes)
                    if end is not None and target > end:
                        target = end
                    fclk += target - ph
                    fclk = (fclk + 0x8000_0000) % _WRAP - 0x8000_0000
                    S[i_fclk] = fclk
                    ph = target
                    continue
            else:
                left -= 1
                if t.debt:
                    t.debt -= 1
                elif t.busy_until <= ph:
                    S[i_tnum] = t.id
                    d.phase = ph  # for the time stamp of messages
                    try:
                        r = t.gen.send(budget)  # type: ignore[union-attr]
                    except (StopIteration, TaskExit):
                        d._stop(t)
                    except Exception as exc:  # noqa: BLE001 — a user's fault stops only its task
                        d._stop(t)
                        d.fault(t, exc)
                    else:
                        if type(r) is int:
                            if r < 0:
                                t.debt = -(r // budget)
                        else:
                            kind, amount, b = r
                            debt = -(b // budget) if b < 0 else 0
                            if kind == SLEEP:
                                t.wake = (
                                    ph + debt + (-(-amount * rate // 1000) if amount > 0 else 0)
                                )
                            else:
                                t.busy_until = (
                                    ph
                                    + debt
                                    + (-(-amount * wait_num // 1_000_000) if amount > 0 else 0)
                                )
            ph += 1
            fclk += 1
            if fclk > _FCLK_MAX:
                fclk -= _WRAP
            S[i_fclk] = fclk
            if pg.mode != IDLE:
                p = axis.step()
                S[i_xref] = round_int(p)
                S[i_ref] = p
                ST[b_run] = 1 if pg.mode != IDLE else 0
                if switches:
                    d._sync_axis()
            if store.input_written:
                d._refresh_inputs()
    finally:
        d.phase = ph
        d._cur, d._left = cur, left
    return done
