# Cython declarations augmenting sensors.py (the optional compiled build: see
# motionvm/compiled_build.py). The .py file is the only source of the code: this file
# makes `Sensors` an extension type whose quiet interval the drive reads directly, and
# the inputs and touch probe words the cycle reads C ints (ints of their objects' ranges).
import cython

@cython.final
cdef class Sensors:
    cdef public object _edge_inputs
    cdef public object _edges
    cdef public long long _external
    cdef public object _gap_bands
    cdef public object _home_high
    cdef public object _home_low
    cdef public object _home_prev
    cdef public object _index_high
    cdef public object _index_low
    cdef public object _index_n
    cdef public object _index_offset
    cdef public object _index_spacing
    cdef public object _negative_limit
    cdef public object _positive_limit
    cdef public object _probe_prev
    cdef public object _switch_external
    cdef public object _switch_high
    cdef public object _switch_inputs
    cdef public object _switch_low
    cdef public int _tp_function
    cdef public object _tp_function_prev
    cdef public bint has_switches
    cdef public object latched
    cdef public object on_change
    cdef public double quiet_high
    cdef public long long quiet_inputs
    cdef public double quiet_low
    cdef public int tp_status

    cpdef bint clear_of_limits(self, lo, hi) except -1
