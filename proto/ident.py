"""Bit-identity: the stepped bench case after `secs` s; every axis's pos_fb, ref_pos, position_actual."""
import hashlib, sys
sys.path.insert(0, "bench")
import motion
import motionvm.motion.axis_cycle as ac
print("axis_cycle:", ac.__file__.rsplit("/", 1)[-1])
secs = float(sys.argv[1]) if len(sys.argv) > 1 else 2.0
for n in (1, 8, 64):
    sim = motion.simulation(n)
    sim.run(until=secs)
    axes = sim.controller.motion.axes
    text = repr([(a.pos_fb, a.ref_pos, a.ref_vel, a.ref_acc, a.drive.position_actual, a.drive.mechanics.position,
                  a.pg._out, a.moving, a.in_pos) for a in axes])
    print(n, hashlib.sha256(text.encode()).hexdigest()[:16], text[:120])
