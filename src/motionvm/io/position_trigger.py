"""Position trigger (PT, manual chapter 12): pulses at programmed positions of an axis.

A `PositionTrigger` is the PT output of one axis's drive. It is fed each cycle with the
axis's feedback position [mm or deg]; the pulses fall at the exact positions, their times
interpolated linearly between the position samples of two cycles (the sample of cycle
c is stamped c * dt, as the scope stamps it). `PositionTriggers` holds one per axis and
is a cycle client of the controller (runtime/clients.py): busy while a PT is armed and
its axis moves toward its next position, stepped after the motion step.

Two modes; the one last configured is used by EnablePT:
- equal interval (SetPT_StartPos, SetPT_EndPos, SetPT_Interval): positions start,
  start +- interval, ... up to end, floor(|end - start| / interval) + 1 of them, in the
  direction from start to end (the manual's examples: start 10, end 20 while moving
  positive; start 20, end 10 while moving negative);
- array (SetPT_PosArray, SetPT_StateArray, SetPT_StartIndex, SetPT_EndIndex): positions
  pos[start_index] ... pos[end_index], in index order (downwards if end < start); they
  must run strictly one way. Bit i % 32 of state word i // 32 says whether position i
  outputs its pulse (1, the default for every position) or passes silently (0).

Decisions where the manual is silent:
- A position fires once, when the feedback reaches it (within half an encoder count, as
  the drive compares counts) while moving in the train's direction; positions the axis
  is already beyond when the PT is enabled are skipped.
  After the last position the PT turns itself off (IsPTEnabled 0).
- The velocity rule of 12.1.1, velocity < interval x position sampling frequency (the
  drive key `pt_sample_rate`, default 16 kHz; the smallest gap of an array): EnablePT
  fails with eERR_AXIS_CMD_INVALID_VEL if the axis moves that fast or its next profile
  move would (its velocity setting times its velocity scale); while the PT is armed a
  move that would reach it is refused with the same code (`Axis.move_vel_limit`).
- The drive must have been homed (12.1): EnablePT on an axis that is not homed fails with
  eERR_AXIS_CMD_INVALID_STATE. Bad arguments: eERR_AXIS_CMD_INVALID_PARAMETER, as is an
  equal-interval train whose count of positions overflows (start -1e308, end 1e308).
- An equal-interval train is computed position by position as the axis reaches them,
  so its length costs no memory.
- Settings changed while the PT is armed apply at the next EnablePT.
- `pt_count` counts every pulse since power-on; the output is active high.
- Memory stays bounded however long the run: `pulses` keeps the latest pulses only
  (at least `PULSES_KEPT`, at most twice as many), enough for the output's level; the
  exact edges of `axisN.pt_out` for a VCD file are kept only by the channels a scope
  recording records (`_Output.record_edges`, called as the recording attaches), from
  then on, and go with the recording. A channel only read (a host's `read`) keeps none.
"""

from __future__ import annotations

import math
import weakref
from bisect import bisect_right
from collections.abc import Callable, Iterable, Sequence

from motionvm.motion import axis_status as st
from motionvm.motion.axis_status import AxisCommandError
from motionvm.runtime.clients import PassiveClient
from motionvm.runtime.scope import BIT_UNIT, RAW_UNIT, ChannelSource, EdgeGetter, ScopeError
from motionvm.runtime.waits import Waiting

N_POSITIONS = 256
N_STATE_WORDS = 8
WIDTH_MIN_NS, WIDTH_MAX_NS, WIDTH_STEP_NS = 20, 80_000, 20
INTERVAL, ARRAY = "interval", "array"
PULSES_KEPT = 1024
"""Pulses `PositionTrigger.pulses` keeps at least (the latest; at most twice as many)."""
MAX_TRAIN = 2.0**53
"""Most positions of an equal-interval train: beyond it consecutive positions are no longer
distinct doubles (start 0, end 1e308, interval 1 is refused like an infinite count)."""


class PositionTrigger:
    """The PT of one axis (see the module docstring)."""

    def __init__(self, axis, homing, dt: float, on_change=None) -> None:
        self.axis = axis
        self.on_change = on_change
        """Called when the PT is armed or disarmed (the bank keeps its armed list)."""
        self.homing = homing
        self.dt = dt
        self.mode = INTERVAL
        self.start_pos = self.end_pos = 0.0
        self.interval = 0.0
        """[mm or deg]; 0: not set."""
        self.width_ns = 1000
        self.positions = [0.0] * N_POSITIONS
        self.states = [0xFFFFFFFF] * N_STATE_WORDS
        self.start_index = self.end_index = 0
        self.enabled = False
        self.count = 0
        """Pulses output since power-on."""
        self.pulses: list[tuple[float, float]] = []
        """(sim_time [s], position [mm or deg]) of the latest pulses output, in time order
        (at least the last `PULSES_KEPT`, at most twice as many)."""
        self._outputs: weakref.WeakSet[_Output] = weakref.WeakSet()
        """The recorded `pt_out` channels, each keeping the pulse times it has seen."""
        self._points: Sequence[tuple[float, bool]] = []
        self._next = 0
        self._direction = 0
        self._x = 0.0
        self._t = 0.0
        self._eps = 0.0

    # ---- settings -------------------------------------------------------------------

    def _bad(self, what: str) -> AxisCommandError:
        return AxisCommandError(st.CMD_INVALID_PARAMETER, f"axis {self.axis.axis_id}: {what}")

    def set_position(self, which: str, pos: float) -> None:
        if not math.isfinite(pos):
            raise self._bad(f"PT {which} position {pos!r}")
        setattr(self, f"{which}_pos", float(pos))
        self.mode = INTERVAL

    def set_interval(self, interval: float) -> None:
        if not (math.isfinite(interval) and interval > 0.0):
            raise self._bad(f"PT interval {interval!r} must be above 0")
        self.interval = float(interval)
        self.mode = INTERVAL

    def set_width(self, width_ns: int) -> None:
        if not WIDTH_MIN_NS <= width_ns <= WIDTH_MAX_NS or width_ns % WIDTH_STEP_NS:
            raise self._bad(
                f"PT pulse width {width_ns} ns is not {WIDTH_MIN_NS}..{WIDTH_MAX_NS} "
                f"in steps of {WIDTH_STEP_NS}"
            )
        self.width_ns = width_ns

    def set_array_position(self, index: int, pos: float) -> None:
        if not 0 <= index < N_POSITIONS:
            raise self._bad(f"PT position index {index} is not 0..{N_POSITIONS - 1}")
        if not math.isfinite(pos):
            raise self._bad(f"PT position {pos!r}")
        self.positions[index] = float(pos)
        self.mode = ARRAY

    def set_state_word(self, index: int, state: int) -> None:
        if not 0 <= index < N_STATE_WORDS:
            raise self._bad(f"PT state index {index} is not 0..{N_STATE_WORDS - 1}")
        self.states[index] = state & 0xFFFFFFFF
        self.mode = ARRAY

    def set_index(self, which: str, index: int) -> None:
        if not 0 <= index < N_POSITIONS:
            raise self._bad(f"PT {which} index {index} is not 0..{N_POSITIONS - 1}")
        setattr(self, f"{which}_index", index)
        self.mode = ARRAY

    # ---- the train ------------------------------------------------------------------

    def train(self) -> Sequence[tuple[float, bool]]:
        """The positions of the configured mode, in order, with their output flag."""
        if self.mode == INTERVAL:
            if self.interval <= 0.0:
                raise self._bad("PT interval not set")
            span = self.end_pos - self.start_pos
            count = abs(span) / self.interval * (1 + 1e-12)
            if not count < MAX_TRAIN:  # start -1e308, end 1e308; or NaN
                raise self._bad(
                    f"PT from {self.start_pos:g} to {self.end_pos:g} every {self.interval:g}: "
                    "more positions than any count"
                )
            n = math.floor(count) + 1
            return _Interval(self.start_pos, math.copysign(self.interval, span), n)
        a, b = self.start_index, self.end_index
        order = range(a, b + 1) if b >= a else range(a, b - 1, -1)
        out = [(self.positions[i], bool(self.states[i // 32] >> (i % 32) & 1)) for i in order]
        gaps = [q[0] - p[0] for p, q in zip(out, out[1:])]
        if gaps and not (all(g > 0 for g in gaps) or all(g < 0 for g in gaps)):
            raise self._bad(f"PT positions of indices {a}..{b} do not run strictly one way")
        return out

    def velocity_limit(self, points: Sequence[tuple[float, bool]]) -> float:
        """The velocity the axis must stay below (12.1.1) [mm/s or deg/s]."""
        if isinstance(points, _Interval):
            gap = self.interval
        else:
            gaps = [abs(q[0] - p[0]) for p, q in zip(points, points[1:])]
            gap = min(gaps, default=math.inf)
        return gap * self.axis.drive.pt_sample_rate

    def enable(self, cycle: int) -> None:
        """Arm the train; AxisCommandError (the manual's code) if it cannot run."""
        a = self.axis
        if not self.homing.homed:
            raise AxisCommandError(
                st.CMD_INVALID_STATE, f"axis {a.axis_id} is not homed (PT needs a homed drive)"
            )
        points = self.train()
        limit = self.velocity_limit(points)
        planned = a.pg.v_max * a.vel_scale / 100.0
        v = max(abs(a.vel_fb), abs(a.ref_vel), planned)
        if v >= limit:
            raise AxisCommandError(
                st.CMD_INVALID_VEL,
                f"axis {a.axis_id}: velocity {v:g} is not below PT interval x sampling "
                f"frequency = {limit:g}",
            )
        x = a.pos_fb
        d = 0 if len(points) == 1 else (1 if points[-1][0] > points[0][0] else -1)
        # the drive compares encoder counts: a position within half a count is reached
        self._eps = eps = 0.5 / a.cpu
        # the first position not yet passed (positions run one way: a binary search)
        skip, hi = 0, len(points)
        while skip < hi:
            mid = (skip + hi) // 2
            if d * (x - points[mid][0]) > eps:
                skip = mid + 1
            else:
                hi = mid
        self._points, self._next, self._direction = points, skip, d
        self._x, self._t = x, (cycle - 1) * self.dt
        self.enabled = True
        a.move_vel_limit = limit
        if self.on_change is not None:
            self.on_change()
        if skip == len(points):
            self.disable()

    def disable(self) -> None:
        self.enabled = False
        self.axis.move_vel_limit = math.inf
        if self.on_change is not None:
            self.on_change()

    def heading(self) -> bool:
        """True while armed and the axis moves toward its next position."""
        if not self.enabled:
            return False
        a = self.axis
        p = self._points[self._next][0]
        v = a.ref_vel or a.vel_fb
        return (
            v != 0.0
            and (self._direction == 0 or v * self._direction > 0)
            and ((p - a.pos_fb) * v >= 0.0)
        )

    def step(self, cycle: int) -> None:
        """Take the feedback sample of cycle `cycle` (stamped cycle * dt)."""
        x1, t1 = self.axis.pos_fb, cycle * self.dt
        x0, t0 = self._x, self._t
        self._x, self._t = x1, t1
        if x1 == x0:
            return
        points, d, i = self._points, self._direction, self._next
        eps = self._eps
        while i < len(points):
            p, out = points[i]
            if d > 0:
                hit = x1 > x0 and p <= x1 + eps
            elif d < 0:
                hit = x1 < x0 and p >= x1 - eps
            else:
                hit = min(x0, x1) - eps <= p <= max(x0, x1) + eps
            if not hit:
                break
            if out:
                self.count += 1
                frac = min(1.0, max(0.0, (p - x0) / (x1 - x0)))
                self._pulse(t0 + (t1 - t0) * frac, p)
            i += 1
        self._next = i
        if i == len(points):
            self.disable()

    # ---- the output -----------------------------------------------------------------

    def _pulse(self, t: float, p: float) -> None:
        """Output a pulse at `t` [s], position `p`; keep it as long as it is needed."""
        pulses = self.pulses
        pulses.append((t, p))
        if len(pulses) >= 2 * PULSES_KEPT:
            del pulses[:PULSES_KEPT]
        for output in self._outputs:
            output.times.append(t)

    def level_at(self, sim_time: float) -> int:
        """The output level at `sim_time` [s]: 1 inside a pulse."""
        width = self.width_ns * 1e-9
        k = bisect_right(self.pulses, (sim_time, math.inf))
        for t, _ in reversed(self.pulses[max(0, k - 4) : k]):
            if t <= sim_time < t + width:
                return 1
        return 0

    def edges(self, times: Iterable[float]) -> list[tuple[float, int]]:
        """(sim_time [s], level) of every change of the output made by pulses at `times`
        (in time order), at the current pulse width."""
        width = self.width_ns * 1e-9
        out: list[tuple[float, int]] = []
        for t in times:
            if out and out[-1][0] > t:  # pulses closer than their width merge
                out[-1] = (t + width, 0)
                continue
            out += [(t, 1), (t + width, 0)]
        return out


class _Interval:
    """The positions of an equal-interval train, computed as they are needed: a train
    of a billion positions (start -1e9, end 1e9, interval 1 um) is armed at once and
    takes no memory."""

    __slots__ = ("n", "start", "step")

    def __init__(self, start: float, step: float, n: int) -> None:
        self.start, self.step, self.n = start, step, n

    def __len__(self) -> int:
        return self.n

    def __getitem__(self, k: int) -> tuple[float, bool]:
        i = k + self.n if k < 0 else k
        if not 0 <= i < self.n:
            raise IndexError(k)
        return self.start + i * self.step, True


class _Output(EdgeGetter):
    """The scope getter of `axisN.pt_out`: the level now, and its exact edges (VCD) since
    a recording started keeping them (the pulse times it keeps go with it)."""

    def __init__(self, pt: PositionTrigger, clock) -> None:
        self.pt, self.clock = pt, clock
        self.times: list[float] = []
        """The times of the pulses since `record_edges` (none before)."""

    def record_edges(self) -> None:
        """Keep the time of every pulse from now on, for `edges` (a recording's channel)."""
        self.pt._outputs.add(self)

    def __call__(self) -> int:
        return self.pt.level_at(self.clock.cycle * self.pt.dt)

    def edges(self) -> list[tuple[float, int]]:
        return self.pt.edges(self.times)


CHANNELS = ("pt_count", "pt_out", "pt_enabled")


class PositionTriggers(PassiveClient, ChannelSource):
    """The PT of every axis: a cycle client of the controller and a scope source
    (nothing before the tasks: `begin_cycle` is `PassiveClient`'s)."""

    def __init__(self, motion, clock) -> None:
        self.clock = clock
        self.triggers = [
            PositionTrigger(a, h, motion.dt, self._armed_changed)
            for a, h in zip(motion.axes, motion.homing)
        ]
        self.armed: list[PositionTrigger] = []
        """The triggers that are enabled (the cycle looks at these only)."""

    @property
    def observes_motion(self) -> bool:
        """An armed trigger samples its axis's feedback every cycle."""
        return bool(self.armed)

    def _armed_changed(self) -> None:
        self.armed = [pt for pt in self.triggers if pt.enabled]
        self.work_changed()

    def has_work(self, hook: str) -> bool:
        """`end_cycle` has work while a PT is armed (runtime/clients.py)."""
        return bool(self.armed)

    def __getitem__(self, axis_id: int) -> PositionTrigger:
        return self.triggers[axis_id]

    # ---- cycle client ---------------------------------------------------------------

    def end_cycle(self) -> None:
        """After the motion step: every armed PT takes its axis's position sample."""
        for pt in self.armed:
            pt.step(self.clock.cycle)

    def busy(self) -> bool:
        return bool(self.armed) and any(pt.heading() for pt in self.armed)

    def next_event(self) -> int | None:
        return self.clock.cycle if self.busy() else None

    def still_running(self) -> list:
        return [
            Waiting(f"axis {pt.axis.axis_id} position trigger", why="armed, the axis moving to it")
            for pt in self.armed
            if pt.heading()
        ]

    # ---- scope source ---------------------------------------------------------------

    def resolve(self, name: str) -> tuple[Callable[[], float], str] | None:
        head, dot, var = name.partition(".")
        if not dot or var not in CHANNELS or not head.startswith("axis"):
            return None
        try:
            pt = self.triggers[int(head[4:])]
        except (ValueError, IndexError):
            raise ScopeError(
                f"scope channel '{name}': the machine has axis0..axis{len(self.triggers) - 1}"
            ) from None
        if var == "pt_count":
            return (lambda: pt.count), RAW_UNIT
        if var == "pt_enabled":
            return (lambda: 1 if pt.enabled else 0), BIT_UNIT
        return _Output(pt, self.clock), BIT_UNIT

    def channel_names(self) -> Iterable[str]:
        for i in range(len(self.triggers)):
            yield from (f"axis{i}.{v}" for v in CHANNELS)
