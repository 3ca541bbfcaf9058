# Cython declarations augmenting mechanics.py (optional compiled build; see setup.py).
# The .py file is the only source of the code: this file only types what it holds.
import cython

cdef class _Motor:
    cdef public object counts_per_rev
    cdef public double position
    cdef public double velocity
    cpdef double step_position(self, double r, double dt) except? -1.0
    cpdef bint holds_whole_counts(self, demand) except -1
    cpdef list held_demands(self)
    cpdef land(self, demand, demand_vel, line, x_1, x, v_1, dt)

cdef class IdealMechanics(_Motor):
    cdef public double _counts_per_rev_f
    cdef public double _demand
    cdef public double _demand_vel
    cdef public double _dt
    cdef public object _line
    cdef public double _velocity_before
    cdef public Py_ssize_t delay_cycles
    cdef public object inertia

    @cython.locals(r_0=double, x=double)
    cpdef double step_position(self, double r, double dt) except? -1.0
    cpdef bint holds_whole_counts(self, demand) except -1
    cpdef list held_demands(self)
    cpdef land(self, demand, demand_vel, line, x_1, x, v_1, dt)
