"""The axis of a simulated PDL drive: the manual's profile generator behind X_* variables.

Adapter, on purpose small: the drive's system variables (`X_vel_max`, `X_acc`, `X_dcc`,
`X_new_sm_fac`, `X_trg`, `X_jvl`, `X_stop_m`) drive a `motion.profile.ProfileGenerator`
stepped once per phase, and the drive reads back `x_ref_pos`, `ref_pos[0]`, `x_run`,
`x_home` and the left limit. This is the drive firmware's reference only: on a machine
its position is the demand of the axis's CiA 402 drive and mechanics, which the
controller's axis feeds back (machine_drives.py); the switches here are computed from
the reference.

Units are the drive's: positions [count], velocities [count/s], accelerations
[count/s^2], the smoothing factor [ms].
"""

from __future__ import annotations

from dataclasses import dataclass

from motionvm.motion.profile import IDLE, ProfileGenerator


@dataclass
class AxisConfig:
    """Start-up values of the X axis and its switches (None: no such switch)."""

    v_max: float = 100_000.0
    """[count/s]"""
    acc: float = 1_000_000.0
    """[count/s^2]"""
    dcc: float = 1_000_000.0
    """[count/s^2]"""
    position: float = 0.0
    """[count]"""
    home_position: float | None = None
    """Centre of the home switch [count]; x_home is on within home_width of it."""
    home_width: float = 100.0
    """[count]"""
    left_limit: float | None = None
    """LEFT_LIM and X_LL are on at or below this position [count]."""


class PdlAxis:
    """One axis moved by a PDL program through the drive's system variables."""

    def __init__(self, phase_rate: float, config: AxisConfig) -> None:
        self.config = config
        self.dt = 1.0 / phase_rate
        self.pg = ProfileGenerator(
            self.dt, config.v_max, config.acc, config.dcc, 0.0, config.position
        )
        self._pending_smooth: float | None = None

    # ---------------------------------------------------------------- commands

    def write(self, name: str, value: float) -> None:
        """React to a program's write of one of the X_* variables (canonical name)."""
        pg = self.pg
        if name == "X_trg":
            pg.move_to(float(value))
        elif name == "X_jvl":
            pg.move_velocity(float(value))
        elif name == "X_stop_m":
            if value and pg.mode != IDLE:
                pg.stop()
        elif name in ("X_vel_max", "X_acc", "X_dcc"):
            if value > 0:
                key = {"X_vel_max": "v_max", "X_acc": "a_max", "X_dcc": "d_max"}[name]
                pg.set_limits(**{key: float(value)})
        elif name == "X_new_sm_fac":
            self._pending_smooth = max(0.0, float(value)) / 1000.0
            self._apply_smooth()

    def _apply_smooth(self) -> None:
        if self._pending_smooth is not None and self.pg.mode == IDLE:
            self.pg.set_smooth_time(min(self._pending_smooth, 10.0))
            self._pending_smooth = None

    # ---------------------------------------------------------------- state

    def step(self) -> float:
        """Advance one phase; the new reference position [count]."""
        p = self.pg.step()[0]
        if self._pending_smooth is not None:
            self._apply_smooth()
        return p

    @property
    def position(self) -> float:
        return self.pg.output[0]

    @property
    def moving(self) -> bool:
        return self.pg.mode != IDLE

    def home(self) -> bool:
        c = self.config
        return (
            c.home_position is not None and abs(self.position - c.home_position) <= c.home_width / 2
        )

    def left_limit(self) -> bool:
        c = self.config
        return c.left_limit is not None and self.position <= c.left_limit
