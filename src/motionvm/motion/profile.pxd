# Cython declarations augmenting profile.py (optional compiled build; see setup.py).
import cython

@cython.final
cdef class ProfileGenerator:
    cdef public double _base
    cdef public list _buf
    cdef public Py_ssize_t _flush
    cdef public object _from_rest
    cdef public bint _idle
    cdef public double _inv_dt
    cdef public Py_ssize_t _j
    cdef public Py_ssize_t _n
    cdef public Py_ssize_t _n_avg
    cdef public Py_ssize_t _nseg
    cdef public double _out_a
    cdef public double _out_p
    cdef public double _out_v
    cdef public double _p_f
    cdef public object _plan
    cdef public double _seg_half_a
    cdef public Py_ssize_t _seg_i
    cdef public double _seg_p_0
    cdef public double _seg_t_0
    cdef public double _seg_t_1
    cdef public double _seg_v_0
    cdef public object _segs
    cdef public bint _smoothing
    cdef public double _sum
    cdef public bint _tc_done
    cdef public object _v_cmd
    cdef public double a_max
    cdef public double d_max
    cdef public double dt
    cdef public object mode
    cdef public object target
    cdef public double v_max
    cdef public double velocity_scale

    cpdef bint _pending(self) except -1
    cpdef _enter_segment(self, Py_ssize_t i)
    @cython.locals(i=Py_ssize_t)
    cpdef bint _segment_at(self, double tau) except -1

    @cython.locals(n=Py_ssize_t, tau=double, p=double, x=double, n_avg=Py_ssize_t, r=double,
                   buf=list, j=Py_ssize_t, s=double,
                   inv_dt=double, v=double, a=double)
    cpdef tuple step(self)

    # the closed-form advance (time skipping)
    @cython.locals(i=Py_ssize_t)
    cpdef sample(self, n)
    cpdef last_sample(self)
    cpdef bint holds_target(self) except -1
    cpdef bint knows_its_past(self, delay) except -1
    @cython.locals(i=Py_ssize_t)
    cpdef segment_of(self, n)
    cpdef pass_end(self, n_last)
    cpdef span(self, t_a, t_b)
    @cython.locals(seg=Py_ssize_t, n_segs=Py_ssize_t, ps=list, buf=list)
    cpdef tuple outputs(self, n_lo, n_e)
    cpdef flush_room(self, n_from, most)
    cpdef advance(self, k, s, p_last=*)
    @cython.locals(ps=list)
    cpdef list advance_smoothed(self, k, back)
