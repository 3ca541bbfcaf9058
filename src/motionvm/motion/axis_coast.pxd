# Cython declarations augmenting axis_coast.py (the optional compiled build: see
# motionvm/compiled_build.py). The .py file is the only source of the code: this file
# types the axis, generator and drive the orchestration of the closed-form advance
# reads, so that it reads their compiled fields and calls their methods directly.
import cython
from motionvm.drives.cia402 cimport Cia402Drive
from motionvm.motion.axis_cycle cimport AxisCycle
from motionvm.motion.profile cimport ProfileGenerator

@cython.locals(d=Cia402Drive)
cpdef bint _common(AxisCycle a) except -1
@cython.locals(pg=ProfileGenerator)
cpdef coast_cycles(AxisCycle a, wanted, bint past_moving=*, memo=*)
@cython.locals(pg=ProfileGenerator)
cpdef _flush_cycles(AxisCycle a, wanted)
cpdef _longest_safe(AxisCycle a, n_0, k)
@cython.locals(pg=ProfileGenerator, d=Cia402Drive)
cpdef tuple _end(AxisCycle a, s)
cpdef _feedback(AxisCycle a, x)
@cython.locals(pg=ProfileGenerator)
cpdef feedback_after(AxisCycle a, i)
@cython.locals(d=Cia402Drive, pg=ProfileGenerator)
cpdef list _demands(AxisCycle a, s, i_lo, i_hi, p_last=*)
@cython.locals(pg=ProfileGenerator)
cpdef bint _safe(AxisCycle a, n_0, n_e) except -1
@cython.locals(d=Cia402Drive)
cpdef bint _clear(AxisCycle a, lo, hi, v_top) except -1
cpdef coast(AxisCycle a, k, memo=*)
@cython.locals(pg=ProfileGenerator)
cpdef _advance(AxisCycle a, k, end=*)
cpdef _settle_cycles(AxisCycle a, k, e, list feedback)
@cython.locals(d=Cia402Drive)
cpdef _advance_smoothed(AxisCycle a, k)
@cython.locals(d=Cia402Drive)
cpdef _land(AxisCycle a, k, list demands, line, x_1, x, v_1, ref=*)
@cython.locals(d=Cia402Drive)
cpdef bint following(AxisCycle a, link) except -1
cpdef bint clear_following(AxisCycle a, lo, hi, v_top) except -1
@cython.locals(d=Cia402Drive)
cpdef coast_following(AxisCycle a, k, list ps, tuple ref)
