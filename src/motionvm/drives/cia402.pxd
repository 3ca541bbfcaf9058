# Cython declarations augmenting cia402.py (optional compiled build; see setup.py).
import cython
from motionvm.drives.mechanics cimport _Motor
from motionvm.drives.sensors cimport Sensors

@cython.final
cdef class Cia402Drive:
    cdef public object _controlword_prev
    cdef public object _csp_ready
    cdef public double _demand
    cdef public object _encoder
    cdef public object _encoder_lost
    cdef public object _fault
    cdef public object _fe_checked
    cdef public object _fe_window
    cdef public object _following_error
    cdef public object _forced
    cdef public object _limit_lazy
    cdef public object _max_torque
    cdef public object _mode_prev
    cdef public double _motor_position_prev
    cdef public object _on_change
    cdef public object _per_mille_per_nm
    cdef public object _position_demand
    cdef public object _ramp_vel
    cdef public object _settled
    cdef public object _stopped
    cdef public object _target_prev
    cdef public object _timer
    cdef public object _torque_actual
    cdef public object _torque_quiet_neg_nm
    cdef public object _torque_quiet_nm
    cdef public object _velocity_actual
    cdef public object boot_cycles
    cdef public object controlword
    cdef public object device_type
    cdef public object digital_inputs
    cdef public object digital_output_mask
    cdef public object digital_outputs
    cdef public object enable_cycles
    cdef public object error_code
    cdef public object local_demand
    cdef public _Motor mechanics
    cdef public object mode
    cdef public object mode_display
    cdef public object objects
    cdef public object position_actual
    cdef public object pt_sample_rate
    cdef public object quick_stop_decel
    cdef public object quick_stop_option
    cdef public object rated_torque
    cdef public object rated_torque_nm
    cdef public Sensors sensors
    cdef public object state
    cdef public object statusword_base
    cdef public object supported_modes
    cdef public object switch_on_cycles
    cdef public object target_position
    cdef public object target_torque
    cdef public object target_velocity
    cdef object __weakref__

    @cython.locals(x=double, demand=double, s=Sensors)
    cpdef step(self, double dt)

    # the closed-form advance (time skipping)
    @cython.locals(s=Sensors)
    cpdef bint steady(self) except -1
    cpdef demand_for(self, target)
    cpdef demand_shift(self)
    cpdef bint clear_of(self, t_lo, t_hi) except -1
    cpdef land(self, target, demand, demand_vel, line, x_1, x, v_1, dt)
