"""Axis-only workload: the stepped bench's axes stepped by the motion kernel alone (no tasks):
each cycle every axis in position gets a new target (same LCG as the bench)."""
import sys
sys.path.insert(0, "bench")
import motion
n, cycles = int(sys.argv[1]), int(sys.argv[2])
sim = motion.simulation(n)
sim.run(until=0.25)
k = sim.controller.motion
axes = k.axes
seed = 1000
for _ in range(cycles):
    for a in axes:
        if a.in_pos:
            seed = (seed * 1103515245 + 12345) & 0xFFFFFFFF
            a.move_abs(((seed >> 8) & 65535) / 65536.0 * 800.0 - 400.0)
    k.step()
if len(sys.argv) > 3:
    import hashlib; print(hashlib.sha256(repr([(a.pos_fb, a.ref_pos, a.drive.position_actual) for a in axes]).encode()).hexdigest())
