"""Mechanics behind a simulated drive: `ideal` tracking or a `servo` loop with a load.

A model works in motor units: position [counts] (float, not wrapped), velocity
[counts/s], torque [N*m]; `counts_per_rev` converts counts to radians for the torque.
The drive calls exactly one `step_*` method per cycle:

    step_position(r, dt)     CSP: demand r [counts] at the end of the cycle, reached
                             linearly over it (the drive's fine interpolation);
                             returns the new position
    step_velocity(v_ref, dt) CSV: velocity demand [counts/s], held over the cycle
    step_torque(tau, dt)     CST: torque demand [N*m], held over the cycle
    step_free(dt)            power stage off: no torque

`create(config)` builds a model from a dict with key "model" = "ideal" | "servo" and
rejects an unknown key or a bad value naming both.
"""

from __future__ import annotations

import math
from collections import deque
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # numpy is imported where the servo model's matrices are built
    import numpy as np

TWO_PI = 2.0 * math.pi
MAX_DELAY_CYCLES = 10_000
"""Longest delay line of the ideal model [cycles] (each cycle holds one float)."""
MAX_BANDWIDTH = 10_000.0
"""Highest servo bandwidth [Hz]: ten times the fastest controller cycle's Nyquist limit."""
MIN_INERTIA = 1e-9
"""Smallest load inertia [kg*m^2]; below it the loop's gains leave float range."""
MAX_COUNTS_PER_REV = 2**40
_EXACT = 2.0**50
"""Counts below this stay exact integers in float arithmetic, with room for sums."""


def _expm(a: np.ndarray) -> np.ndarray:
    """Matrix exponential by scaling and squaring of a Taylor series (small matrices)."""
    import numpy as np  # only the servo model needs it; ~0.1 s off every other run

    norm = float(np.max(np.sum(np.abs(a), axis=1)))
    squarings = max(0, math.ceil(math.log2(norm)) + 1) if norm > 0.5 else 0
    a = a / 2.0**squarings
    term = np.eye(a.shape[0])
    result = term.copy()
    for k in range(1, 30):
        term = term @ a / k
        result = result + term
    for _ in range(squarings):
        result = result @ result
    return result


class Config:
    """Reads a config dict for `where` (e.g. "mechanics 'servo'"), naming key and value
    in every error."""

    def __init__(self, config: dict, where: str, allowed: frozenset[str]):
        self.config = config
        self.where = where
        unknown = sorted(set(config) - allowed - {"model"})
        if unknown:
            key = unknown[0]
            raise ValueError(
                f"{where}: unknown key {key!r} = {config[key]!r}"
                f" (allowed: {', '.join(sorted(allowed))})"
            )

    def number(
        self, key: str, default: float, low: float = 0.0, strict: bool = True, high: float = 1e6
    ) -> float:
        """A number in `low < x <= high` (`low <= x` unless `strict`); the default upper
        bound keeps products of the loop's gains and inertias inside float range."""
        value = self.config.get(key, default)
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if ok:
            value = float(value)
            ok = math.isfinite(value) and (value > low if strict else value >= low)
            ok = ok and value <= high
        if not ok:
            bound = f"> {low:g}" if strict else f">= {low:g}"
            bound = bound if low > -math.inf else ""
            raise ValueError(
                f"{self.where}: {key} = {value!r} is not a finite number {bound}"
                f"{' and ' if bound else ''}<= {high:g}"
            )
        return value

    def integer(self, key: str, default: int, low: int, high: int = 2**32 - 1) -> int:
        value = self.config.get(key, default)
        if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
            raise ValueError(
                f"{self.where}: {key} = {value!r} is not an integer >= {low} and <= {high}"
            )
        return value


class _Motor:
    """What every model reports: the motor's actual position, velocity and torque."""

    __slots__ = ()  # the models name the attributes

    def _at_rest(self, counts_per_rev: int) -> None:
        """Start at position 0 at rest (the models start without torque)."""
        self.counts_per_rev = counts_per_rev
        self.position = 0.0
        """Actual position [counts]."""
        self.velocity = 0.0
        """Actual velocity [counts/s]."""

    def step_position(self, r: float, dt: float) -> float:
        """Follow demand r [counts] (see the module doc); returns the new position."""
        raise NotImplementedError  # every model has its own (declared in mechanics.pxd)

    def holds_whole_counts(self, demand: float) -> bool:
        """True if the motor's cycles in CSP can be advanced in closed form (`land`):
        its position, its last demand `demand` [counts] and what it has still to reach
        are whole, exact counts. No model but the ideal one can."""
        return False

    def held_demands(self) -> list:
        """The position and the demands still to reach [counts] (`IdealMechanics`)."""
        raise NotImplementedError

    def land(self, demand: float, demand_vel: float, line: list | None, x_1: float, x: float,
             v_1: float, dt: float) -> None:  # fmt: skip
        """The motor after a closed-form advance (`IdealMechanics`)."""
        raise NotImplementedError


class IdealMechanics(_Motor):
    """Feedback follows the demand exactly, `delay_cycles` cycles later.

    CSV integrates the velocity demand, CST accelerates `inertia` with the torque;
    both outputs pass the same delay line. Power off stops the motor at once.

    A cycle stores what its torque follows from (the velocity before it and the cycle
    time) and `torque` computes it when read: the torque's one formula, and no cycle
    pays for it unless someone reads it.
    """

    __slots__ = (  # set up in __init__
        "_counts_per_rev_f", "_demand", "_demand_vel", "_dt", "_line", "_velocity_before",
        "counts_per_rev", "delay_cycles", "inertia", "position", "velocity"
    )  # fmt: skip

    KEYS = frozenset({"delay_cycles", "inertia", "counts_per_rev"})

    def __init__(self, delay_cycles: int = 0, inertia: float = 1e-4, counts_per_rev: int = 1 << 17):
        self.delay_cycles = delay_cycles
        self.inertia = inertia
        """Load inertia [kg*m^2] seen by the motor (CST and the reported torque)."""
        self._at_rest(counts_per_rev)
        self._velocity_before = 0.0
        """Velocity [counts/s] at the start of the last cycle."""
        self._dt = 1.0
        """The last cycle's time [s] (any positive value at rest)."""
        self._counts_per_rev_f = float(counts_per_rev)
        self._line: deque[float] = deque([0.0] * delay_cycles)
        self._demand = 0.0
        """The last position demand [counts]."""
        self._demand_vel = 0.0
        """Velocity of the demand [counts/s] (CST integrates on from it)."""

    @classmethod
    def create(cls, config: dict) -> IdealMechanics:
        cfg = Config(config, "mechanics 'ideal'", cls.KEYS)
        return cls(
            delay_cycles=cfg.integer("delay_cycles", 0, 0, MAX_DELAY_CYCLES),
            inertia=cfg.number("inertia", 1e-4, low=MIN_INERTIA, strict=False),
            counts_per_rev=cfg.integer("counts_per_rev", 1 << 17, 1, MAX_COUNTS_PER_REV),
        )

    @property
    def torque(self) -> float:
        """Actual torque [N*m]: the inertia times the last cycle's change of velocity."""
        # / float(counts_per_rev) is / counts_per_rev (exact below 2**53) without the
        # int's conversion
        return (self.inertia * (self.velocity - self._velocity_before) / self._dt * TWO_PI
                / self._counts_per_rev_f)  # fmt: skip

    def set_position(self, position: float) -> None:
        """Place the motor at `position` [counts], at rest."""
        self.position = self._demand = float(position)
        self.velocity = self._velocity_before = self._demand_vel = 0.0
        self._line = deque([self.position] * self.delay_cycles)

    def step_position(self, r: float, dt: float) -> float:
        """The motor reaches demand r [counts] `delay_cycles` cycles later; the other
        modes are a demand computed from theirs. Returns the new position."""
        r_0 = self._demand
        self._demand_vel = (r - r_0) / dt
        self._demand = r
        if self.delay_cycles == 1:  # the delay line holds the last demand only
            x = r_0
        else:
            line = self._line
            line.append(r)
            x = line.popleft()
        self._velocity_before = self.velocity
        self._dt = dt
        self.velocity = (x - self.position) / dt
        self.position = x
        return x

    # ---- closed-form advance (time skipping: motion/axis_coast.py) -------------------

    def holds_whole_counts(self, demand: float) -> bool:
        """True if the position, the last demand (`demand` [counts]) and the delay line
        are whole counts, exact in float arithmetic with room for sums: then the
        demands of an advance are exact and the motor reaches each of them as it is."""
        if not (-_EXACT < demand < _EXACT and demand % 1.0 == 0.0 and self._demand == demand):
            return False
        if self.delay_cycles > 1:  # (with one cycle of delay the line is not used)
            for x in self._line:  # (a loop, not all(): no closure in the compiled build)
                if not (x % 1.0 == 0.0 and abs(x) < _EXACT):
                    return False
        return self.position % 1.0 == 0.0

    def held_demands(self) -> list:
        """The motor's position [counts], then the demands it has still to reach, oldest
        first (`delay_cycles` of them): the positions of this cycle and the next ones."""
        if self.delay_cycles == 0:
            return [self.position]
        if self.delay_cycles == 1:
            return [self.position, self._demand]
        return [self.position, *self._line]

    def land(self, demand: float, demand_vel: float, line: list | None, x_1: float, x: float,
             v_1: float, dt: float) -> None:  # fmt: skip
        """The motor after an advance in CSP, as `step_position` leaves it: its last cycle
        moved it from x_1 [counts] (velocity v_1 [counts/s] the cycle before) to x, the
        demand that left the delay line; `demand` is the newest demand (its velocity
        `demand_vel` [counts/s]), `line` the delay line before that cycle's demand came
        in, without x (None: the line as it is, with one cycle of delay or none)."""
        self.position, self.velocity = x_1, v_1
        if self.delay_cycles == 1:  # the demand of the cycle before
            self._demand = x
        elif self.delay_cycles > 1:  # x first out, the newest demand back in by the step
            queue = self._line
            if line is not None:
                queue.clear()
                queue.extend(line)
            queue.pop()
            queue.appendleft(x)
        self.step_position(demand, dt)
        self._demand_vel = demand_vel

    def step_velocity(self, v_ref: float, dt: float) -> None:
        self.step_position(self._demand + v_ref * dt, dt)
        self._demand_vel = v_ref

    def step_torque(self, tau: float, dt: float) -> None:
        v_0 = self._demand_vel
        v_1 = v_0 + tau / self.inertia * self.counts_per_rev / TWO_PI * dt
        self.step_position(self._demand + 0.5 * (v_0 + v_1) * dt, dt)
        self._demand_vel = v_1

    def step_free(self, dt: float) -> None:
        self.set_position(self.position)


class ServoMechanics(_Motor):
    """A cascaded P position / P velocity loop tuned for `bandwidth` and `damping`.

    Closed loop (tuned_inertia = inertia, no friction): x'' = wn^2 (r - x) +
    2 zeta wn (ff r' - x'), wn = 2 pi bandwidth, so a ramp of velocity v has the
    following error 2 zeta v / wn (ff = 0) and a step settles in about 4/(zeta wn).
    The loop computes a torque tau = J_tuned * alpha_cmd, clipped to max_torque, that
    drives the load inertia against viscous friction and a constant load torque.

    Integration is exact for piecewise-linear demands (matrix exponential of the linear
    system, computed once per dt), so any bandwidth is stable at any cycle time. When the
    loop torque at the start or the end of a cycle exceeds max_torque, the cycle runs at
    the clipped torque instead (the torque is constant over a cycle then).
    """

    KEYS = frozenset({
        "bandwidth", "damping", "inertia", "tuned_inertia", "friction", "load_torque",
        "max_torque", "velocity_feedforward", "counts_per_rev",
    })  # fmt: skip

    def __init__(
        self,
        bandwidth: float = 50.0,
        damping: float = 0.7,
        inertia: float = 1e-4,
        tuned_inertia: float | None = None,
        friction: float = 0.0,
        load_torque: float = 0.0,
        max_torque: float = math.inf,
        velocity_feedforward: float = 0.0,
        counts_per_rev: int = 1 << 17,
    ):
        self.bandwidth = bandwidth
        """Closed-loop natural frequency [Hz]."""
        self.damping = damping
        """Damping ratio zeta [-]."""
        self.inertia = inertia
        """Load inertia at the motor [kg*m^2]."""
        self.tuned_inertia = inertia if tuned_inertia is None else tuned_inertia
        """Inertia [kg*m^2] the loop gains were tuned for."""
        self.friction = friction
        """Viscous friction [N*m*s/rad]."""
        self.load_torque = load_torque
        """Constant external torque on the load [N*m]."""
        self.max_torque = max_torque
        """Torque limit of the drive [N*m]."""
        self.velocity_feedforward = velocity_feedforward
        """Velocity feed-forward gain [-], 0..1."""
        self._at_rest(counts_per_rev)
        self.torque = 0.0
        """Actual torque [N*m]."""
        self._demand = 0.0
        self._rad = TWO_PI / counts_per_rev  # [rad/count]
        wn = TWO_PI * bandwidth
        self._kp = wn / (2.0 * damping)  # [1/s], position loop
        self._kv = 2.0 * damping * wn  # [1/s], velocity loop
        self._cache: dict[float, tuple] = {}

    @classmethod
    def create(cls, config: dict) -> ServoMechanics:
        cfg = Config(config, "mechanics 'servo'", cls.KEYS)
        inertia = cfg.number("inertia", 1e-4, low=MIN_INERTIA, strict=False)
        ff = cfg.number("velocity_feedforward", 0.0, strict=False)
        if ff > 1.0:
            raise ValueError(f"mechanics 'servo': velocity_feedforward = {ff!r} is not in 0..1")
        return cls(
            bandwidth=cfg.number("bandwidth", 50.0, high=MAX_BANDWIDTH),
            damping=cfg.number("damping", 0.7, low=0.01, strict=False, high=100.0),
            inertia=inertia,
            tuned_inertia=cfg.number("tuned_inertia", inertia, low=MIN_INERTIA, strict=False),
            friction=cfg.number("friction", 0.0, strict=False),
            load_torque=cfg.number("load_torque", 0.0, low=-1e6, strict=False),
            max_torque=cfg.number("max_torque", 1.0) if "max_torque" in config else math.inf,
            velocity_feedforward=ff,
            counts_per_rev=cfg.integer("counts_per_rev", 1 << 17, 1, MAX_COUNTS_PER_REV),
        )

    def set_position(self, position: float) -> None:
        """Place the motor at `position` [counts], at rest."""
        self.position = self._demand = float(position)
        self.velocity = self.torque = 0.0

    def _matrices(self, dt: float) -> tuple:
        """Rows (x, v) of the exact transition for the CSP, CSV and torque dynamics."""
        m = self._cache.get(dt)
        if m is None:
            import numpy as np

            g = self.tuned_inertia / self.inertia
            b = self.friction / self.inertia
            wn2 = self._kp * self._kv
            ff = self.velocity_feedforward
            # CSP: z = [x - r_0, v, rdot, w], r(t) = r_0 + rdot t, w load accel [counts/s^2]
            csp = np.zeros((4, 4))
            csp[0, 1] = 1.0
            csp[0, 2] = -1.0  # x - r(t) changes by v - rdot
            csp[1, 0] = -g * wn2
            csp[1, 1] = -g * self._kv - b
            csp[1, 2] = g * self._kv * ff
            csp[1, 3] = 1.0
            # CSV: z = [x, v, v_ref, w]
            csv = np.zeros((4, 4))
            csv[0, 1] = 1.0
            csv[1, 1] = -g * self._kv - b
            csv[1, 2] = g * self._kv
            csv[1, 3] = 1.0
            # torque: z = [x, v, u], u = tau/J + w [counts/s^2]
            trq = np.zeros((3, 3))
            trq[0, 1] = 1.0
            trq[1, 1] = -b
            trq[1, 2] = 1.0
            m = tuple(tuple(tuple(float(c) for c in _expm(a * dt)[i]) for i in (0, 1))
                      for a in (csp, csv, trq))  # fmt: skip
            self._cache[dt] = m
        return m

    def _to_accel(self, tau: float) -> float:
        return tau / (self.inertia * self._rad)  # [N*m] -> [counts/s^2]

    def _loop_torque(self, r: float, r_dot: float, x: float, v: float) -> float:
        """Torque [N*m] the position loop commands in state (x, v) for demand (r, r_dot)."""
        alpha = self._kv * (self._kp * (r - x) + self.velocity_feedforward * r_dot - v)
        return self.tuned_inertia * alpha * self._rad

    def step_position(self, r: float, dt: float) -> float:
        """Follow demand r [counts]; returns the new position."""
        r_0 = self._demand
        self._demand = r
        r_dot = (r - r_0) / dt
        x_0, v_0 = self.position, self.velocity
        (x_row, v_row), _, _ = self._matrices(dt)
        e, w = x_0 - r_0, self._to_accel(self.load_torque)
        x_1 = r + x_row[0] * e + x_row[1] * v_0 + x_row[2] * r_dot + x_row[3] * w
        v_1 = v_row[0] * e + v_row[1] * v_0 + v_row[2] * r_dot + v_row[3] * w
        tau_0 = self._loop_torque(r_0, r_dot, x_0, v_0)
        tau_1 = self._loop_torque(r, r_dot, x_1, v_1)
        tau = tau_0 if abs(tau_0) > abs(tau_1) else tau_1
        if abs(tau) > self.max_torque:
            self.step_torque(tau, dt)  # clipped to max_torque
            return self.position
        self.position, self.velocity, self.torque = x_1, v_1, tau_1
        return x_1

    def step_velocity(self, v_ref: float, dt: float) -> None:
        _, (x_row, v_row), _ = self._matrices(dt)
        v_0, w = self.velocity, self._to_accel(self.load_torque)
        v_1 = v_row[1] * v_0 + v_row[2] * v_ref + v_row[3] * w
        gain = self.tuned_inertia * self._kv * self._rad
        tau_0, tau_1 = gain * (v_ref - v_0), gain * (v_ref - v_1)
        tau = tau_0 if abs(tau_0) > abs(tau_1) else tau_1
        if abs(tau) > self.max_torque:
            self.step_torque(tau, dt)  # clipped to max_torque
        else:
            self.position += x_row[1] * v_0 + x_row[2] * v_ref + x_row[3] * w
            self.velocity, self.torque = v_1, tau_1
        self._demand = self.position

    def step_torque(self, tau: float, dt: float) -> None:
        tau = max(-self.max_torque, min(self.max_torque, tau))
        self.torque = tau
        _, _, (x_row, v_row) = self._matrices(dt)
        v, u = self.velocity, self._to_accel(tau + self.load_torque)
        self.position += x_row[1] * v + x_row[2] * u
        self.velocity = v_row[1] * v + v_row[2] * u

    def step_free(self, dt: float) -> None:
        self.step_torque(0.0, dt)
        self._demand = self.position


MODELS = {"ideal": IdealMechanics, "servo": ServoMechanics}


def create(config: dict) -> IdealMechanics | ServoMechanics:
    """Build the mechanics model named by config["model"] (default "ideal")."""
    if not isinstance(config, dict):
        raise ValueError(f"mechanics: the configuration must be a table, got {config!r}")  # noqa: TRY004
    model = config.get("model", "ideal")
    cls = MODELS.get(model)
    if cls is None:
        raise ValueError(
            f"mechanics: model = {model!r} is unknown (known: {', '.join(sorted(MODELS))})"
        )
    return cls.create(config)
