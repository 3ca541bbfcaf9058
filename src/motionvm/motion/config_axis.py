"""The axis variables of manual table 17.1.1.2 (0x83IIVVVV), bound to the axes of a
motion kernel: `register(table, kernel)`.

A write takes effect as the axis's own setter would (SetVel, SetSWRL, SetHomeAcc ...,
with their checks and error codes); a value outside a variable's range without such a
setter is eERR_HCV_VALUE_OUT_OF_RANGE. Decisions where the manual is silent:
- motion_type: 0 a linear axis, 1 a rotary one (read-only).
- pos_tr_t, en_delay [ms] are rounded to whole controller cycles.
- vel_lim, acc_lim: the protection range of PVT motion (machine keys vel_limit,
  acc_limit); dec_lim is kept beside them (no motion of the simulation checks it).
- home_status: 1 homed, 0 not (writing it is SetHomedStatus).
- fb_ratio_pos/fb_ratio_cnt: 1 unit per counts_per_unit counts; fb_curr_ratio_curr/cnt:
  the drive's rated torque / torque constant [A] per 1000 counts of its torque objects;
  rotor_inertia the ideal mechanics' inertia, else 0; all read-only (the hardware's).
- force_constant: the torque constant of GetCurrFb [N*m/A], writable.
- last_err: the axis's last error as the C int; writing 0 clears it (ClearAxisLastErr).
- gant_pair: the gantry pair id, -1 if none (read-only); gear_ratio: the gear slave's
  ratio (0 if none); writing it changes the ratio of an engaged slave (GearIn).
- max_comp_lim [mm or deg]: the largest error compensation the axis accepts (1 by
  default, 14.1); a write (above 0) bounds the tables of later SetupComp* calls and the
  compensation from the next cycle on (beyond it: error stop, eERR_AXIS_COMP_LIMIT).
- Variables of the vendor's HMI with nothing behind them in a simulation (p2p_del, p2p_pos1, p2p_pos2, p2p_repeat, rlt_dist, en_motionManager, map_io_type) keep
  the value written (default 0) and change nothing.
"""

from __future__ import annotations

import dataclasses
import math

from motionvm.motion.config_vars import AXIS, ConfigVarTable, manual_ids


def _finite(value: float, low: float = -math.inf, strict_low: bool = False) -> float:
    if not math.isfinite(value) or value < low or (strict_low and value == low):
        raise ValueError(f"{value!r} is out of range")
    return value


def register(table: ConfigVarTable, kernel) -> None:
    """Register every axis variable of table 17.1.1.2 for the axes of `kernel`."""
    axes = kernel.axes
    table.add_family(AXIS, lambda i: 0 <= i < len(axes))
    stored: dict[tuple[int, str], float] = {}
    dec_limits = {a.axis_id: a.config.acc_limit for a in axes}

    def ax(attr):
        return lambda i: float(getattr(axes[i], attr))

    def call(method):
        return lambda i, v: getattr(axes[i], method)(v)

    def home(attr):
        return lambda i: float(getattr(kernel.homing[i].settings, attr))

    def home_set(method):
        return lambda i, v: getattr(kernel.homing[i], method)(v)

    def config_set(key, strict=True):
        def set_(i, v):
            a = axes[i]
            a.config = dataclasses.replace(a.config, **{key: _finite(v, 0.0, strict)})

        return set_

    def inpos_radius(i, v):
        axes[i].inpos_radius = _finite(v, 0.0, strict_low=True)

    def max_pos_err(i, v):
        axes[i].wake()
        axes[i].max_pos_err = _finite(v, 0.0, strict_low=True)

    def set_ms(attr):
        def set_(i, v):
            setattr(axes[i], attr, _finite(v, 0.0))

        return set_

    def comp_lim_set(i, v):
        axes[i].wake()
        axes[i].filters.comp_limit = _finite(v, 0.0, strict_low=True)

    def dec_lim_set(i, v):
        dec_limits[i] = _finite(v, 0.0, strict_low=True)

    def last_err_set(i, v):
        if v != 0:
            raise ValueError("only 0 (clear) can be written")
        axes[i].last_error = 0

    def gear_ratio_set(i, v):
        g = kernel.gears.gear_of(i)
        if g is None:
            raise ValueError(f"axis {i} is no gear slave")
        kernel.gears.gear_in(g.master, axes[i], _finite(v))

    def cur_ratio(i):
        a = axes[i]
        return a.drive.rated_torque_nm / a.config.torque_constant

    def inertia(i):
        return float(getattr(axes[i].drive.mechanics, "inertia", 0.0))

    def keep(name):
        return (lambda i: stored.get((i, name), 0.0)), (
            lambda i, v: stored.__setitem__((i, name), _finite(v))
        )

    bindings = {
        "motion_type": (lambda i: 1.0 if axes[i].rotary else 0.0, None),
        "pos_tr": (ax("inpos_radius"), inpos_radius),
        "pos_tr_t": (ax("inpos_debounce_ms"), set_ms("inpos_debounce_ms")),
        "sw_RL": (ax("sw_right"), call("set_sw_right")),
        "sw_LL": (ax("sw_left"), call("set_sw_left")),
        "vel_lim": (lambda i: axes[i].config.vel_limit, config_set("vel_limit")),
        "acc_lim": (lambda i: axes[i].config.acc_limit, config_set("acc_limit")),
        "dec_lim": (lambda i: dec_limits[i], dec_lim_set),
        "max_pos_err": (ax("max_pos_err"), max_pos_err),
        "max_comp_lim": (lambda i: axes[i].filters.comp_limit, comp_lim_set),
        "home_status": (lambda i: 1.0 if kernel.homing[i].homed else 0.0,
                        lambda i, v: kernel.homing[i].set_homed(int(v) if v in (0, 1) else 2)),
        "home_method": (home("method"), lambda i, v: kernel.homing[i].set_method(int(v))),
        "home_fast_vel": (home("switch_vel"), home_set("set_switch_vel")),
        "home_slow_vel": (home("zero_vel"), home_set("set_zero_vel")),
        "home_timeout": (home("timeout_ms"), home_set("set_timeout")),
        "home_acc": (home("acc"), home_set("set_acc")),
        "home_offset": (home("offset"), home_set("set_offset")),
        "max_vel": (lambda i: axes[i].pg.v_max, call("set_vel")),
        "max_acc": (lambda i: axes[i].pg.a_max, call("set_acc")),
        "max_dec": (lambda i: axes[i].pg.d_max, call("set_dec")),
        "sm_factor": (ax("smooth_time_ms"), call("set_smooth_time")),
        "vel_scale": (ax("vel_scale"), call("set_vel_scale")),
        "acc_time": (lambda i: axes[i].pg.v_max / axes[i].pg.a_max * 1000.0,
                     call("set_acc_time")),
        "dec_time": (lambda i: axes[i].pg.v_max / axes[i].pg.d_max * 1000.0,
                     call("set_dec_time")),
        "rollover_turns": (ax("rollover_turns"), None),
        "rollover_val": (ax("rollover"), call("set_rollover")),
        "gant_pair": (lambda i: float(kernel.gantries.pair_id(i)), None),
        "en_delay": (ax("enable_timeout_ms"), set_ms("enable_timeout_ms")),
        "fb_ratio_pos": (lambda i: 1.0, None),
        "fb_ratio_cnt": (ax("cpu"), None),
        "fb_curr_ratio_curr": (cur_ratio, None),
        "fb_curr_ratio_cnt": (lambda i: 1000.0, None),
        "rotor_inertia": (inertia, None),
        "force_constant": (lambda i: axes[i].config.torque_constant,
                           config_set("torque_constant")),
        "last_err": (ax("last_error"), last_err_set),
        "gear_ratio": (lambda i: kernel.gears.ratio(i), gear_ratio_set),
    }  # fmt: skip
    for name in ("p2p_del", "p2p_pos1", "p2p_pos2", "p2p_repeat", "rlt_dist",
                 "en_motionManager", "map_io_type"):  # fmt: skip
        bindings[name] = keep(name)
    for var, name in manual_ids()[AXIS]:
        get, set_ = bindings[name.removeprefix("HCV_ID_")]
        table.add(AXIS, var, name, get, set_)
