# Cython declarations augmenting axis_cycle.py (optional compiled build; see setup.py).
# The int32 counts of a cycle (position actual, its change, the target's change) and
# the small ints it compares (reference source, op mode, digital inputs) are C integers:
# the same values as Python's ints, compared and wrapped in C.
# AxisCycle becomes an extension type holding the cycle's state; `Axis` (axis.py) stays
# a Python class deriving from it. Its flags are C ints (bint: True and False read back
# as before), its cycle time and counts per unit C doubles (the same float arithmetic:
# an int below 2**53 converts exactly), and the module's constants C ints: the cycle
# makes no Python object in its common case. `_round` is C's rint (cia402.pxd).
import cython
from motionvm.drives.cia402 cimport Cia402Drive, _round
from motionvm.drives.sensors cimport Sensors
from motionvm.motion.profile cimport ProfileGenerator

cdef int _PG, _PVT, _RAMP, _TORQUE, _EXT, _MODE_CSP, _MODE_CSV
cdef int CW_DISABLE, CW_SHUTDOWN, CW_ENABLE, CW_FAULT_RESET
cdef long long _TWO_31, _MASK_32
cdef long _SW_CYCLIC, _FS_HW_LIMITS

cdef class AxisCycle:
    cdef public object _cmd_path
    cdef public object _command_queue
    cdef public object _comp_dependents
    cdef public long long _cycle
    cdef public object _deferred_move
    cdef public long long _digital_inputs
    cdef public object _enable_cycles
    cdef public object _enable_timeout_cycles
    cdef public bint _enabling
    cdef public object _error_stop
    cdef public object _fault_reset_cycles
    cdef public long long _feedback_counts
    cdef public object _ignore_swl
    cdef public object _in_pos_cycles
    cdef public object _in_pos_debounce_cycles
    cdef public object _last_snapshot
    cdef public double _max_pos_err
    cdef public double _min_pos_err
    cdef public object _move_end_cycle
    cdef public object _move_start_cycle
    cdef public bint _on_hw_limit
    cdef public object _pos_offset
    cdef public long long _position_actual
    cdef public object _provider
    cdef public object _pvt_cycle
    cdef public object _pvt_trajectory
    cdef public object _ramp_decel
    cdef public object _ramp_vel
    cdef public int _reference_source
    cdef public object _rest_after_cycles
    cdef public object _rollover
    cdef public double _slave_offset
    cdef public object _still_cycles
    cdef public object _sw_left
    cdef public object _sw_right
    cdef public double _sw_stop_left
    cdef public double _sw_stop_right
    cdef public object _torque_per_mille
    cdef public object axis_id
    cdef public object comp_pos
    cdef public double cpu
    cdef public Cia402Drive drive
    cdef public double dt
    cdef public bint enabled
    cdef public object fault_status
    cdef public object halted
    cdef public object ignore_hwl
    cdef public bint ignore_pe
    cdef public bint in_pos
    cdef public object inpos_radius
    cdef public object kill_dec
    cdef public object last_error
    cdef public object move_time_ms
    cdef public bint moving
    cdef public int op_mode
    cdef public ProfileGenerator pg
    cdef public double pos_fb
    cdef public double pos_fb_raw
    cdef public double ref_acc
    cdef public double ref_pos
    cdef public double ref_vel
    cdef public bint resting
    cdef public object settling_time_ms
    cdef public object stopping

    @cython.locals(drive=Cia402Drive, pg=ProfileGenerator, s=Sensors, n=Py_ssize_t,
                   tau=double, x=double, inv_dt=double,
                   p=double, v=double, a=double, demand=double, raw=double,
                   pos_fb=double, err=double, enabled=bint, change=longlong,
                   position_actual=longlong, delta=longlong, counts=longlong,
                   enc=longlong, digital_inputs=longlong, src=int, moving=bint)
    cpdef step(self)
    @cython.locals(p=double, v=double, a=double, err=double, position_actual=longlong,
                   delta=longlong, counts=longlong, mode=int, digital_inputs=longlong)
    cpdef bint _step_general(self, Cia402Drive drive) except -1
    cpdef _software_limit(self, double p, double v)
    cpdef _settle(self)
    cpdef bint _idle_candidate(self) except -1
    cpdef _watch_rest(self)
    cpdef tuple _snapshot(self)

@cython.locals(a=AxisCycle)
cpdef step_axes(list axes)

@cython.locals(a=AxisCycle)
cpdef bint axes_busy(list axes) except -1

@cython.locals(a=AxisCycle, k=Py_ssize_t)
cpdef Py_ssize_t step_axes_alone(list order, list axes, Py_ssize_t n, bint until_idle) except -1
