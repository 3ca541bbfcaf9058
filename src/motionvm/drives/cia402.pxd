# Cython declarations augmenting cia402.py (optional compiled build; see setup.py).
# The fields of the common cycle are C ints (the controlword, the mode, the int32
# targets and actual values, the flags), its constants C ints too: the drive's cycle
# makes no Python object. Every value they take is an int of its object's range (the
# object dictionary checks what it stores) or a bool (bint reads back True or False).
import cython
from libc.math cimport rint
from motionvm.drives.mechanics cimport _Motor
from motionvm.drives.sensors cimport Sensors

# round(x) of a float (the .py files' `_round`, float.__round__ in pure Python): C's
# rint, which rounds half to even as `round` does, in the current rounding mode (to
# nearest: nothing here changes it); beyond +-2**62 (no motion gets there) Python's
# round, wrapped to int32 at once (the same int32 value; inf and nan raise as before)
cdef inline long long _round(double x) except? -1:
    if -4.6e18 < x < 4.6e18:
        return <long long>rint(x)
    return ((round(x) + 0x80000000) & 0xFFFFFFFF) - 0x80000000

cdef int _CSP, _CW_ENABLE
cdef long long _TWO_31, _MASK_32
cdef long _SW_CYCLIC

@cython.final
cdef class Cia402Drive:
    cdef public int _controlword_prev
    cdef public bint _csp_ready
    cdef public double _demand
    cdef public long long _encoder
    cdef public bint _encoder_lost
    cdef public object _fault
    cdef public bint _fe_checked
    cdef public object _fe_window
    cdef public object _following_error
    cdef public dict _forced
    cdef public bint _limit_lazy
    cdef public object _max_torque
    cdef public object _mode_prev
    cdef public double _motor_position_prev
    cdef public object _on_change
    cdef public object _per_mille_per_nm
    cdef public object _position_demand
    cdef public object _ramp_vel
    cdef public object _settled
    cdef public object _stopped
    cdef public long long _target_prev
    cdef public object _timer
    cdef public object _torque_actual
    cdef public object _torque_quiet_neg_nm
    cdef public object _torque_quiet_nm
    cdef public object _velocity_actual
    cdef public object boot_cycles
    cdef public int controlword
    cdef public object device_type
    cdef public long long digital_inputs
    cdef public object digital_output_mask
    cdef public object digital_outputs
    cdef public object enable_cycles
    cdef public object error_code
    cdef public object local_demand
    cdef public _Motor mechanics
    cdef public int mode
    cdef public object mode_display
    cdef public object objects
    cdef public long long position_actual
    cdef public object pt_sample_rate
    cdef public object quick_stop_decel
    cdef public object quick_stop_option
    cdef public object rated_torque
    cdef public object rated_torque_nm
    cdef public Sensors sensors
    cdef public object state
    cdef public long statusword_base
    cdef public object supported_modes
    cdef public object switch_on_cycles
    cdef public long long target_position
    cdef public object target_torque
    cdef public object target_velocity
    cdef object __weakref__

    @cython.locals(x=double, demand=double, s=Sensors, target="long long",
                   change="long long", enc="long long", fe="long long")
    cpdef step(self, double dt)

    # the closed-form advance (time skipping)
    @cython.locals(s=Sensors)
    cpdef bint steady(self) except -1
    cpdef demand_for(self, target)
    cpdef demand_shift(self)
    cpdef bint clear_of(self, t_lo, t_hi) except -1
    cpdef land(self, target, demand, demand_vel, line, x_1, x, v_1, dt)
