"""Run the stepped bench case: build simulation(n), run to 0.25 s, then `secs` more (for cachegrind)."""
import sys
sys.path.insert(0, "bench")
import motion  # noqa: E402
n, secs = int(sys.argv[1]), float(sys.argv[2])
sim = motion.simulation(n)
sim.run(until=0.25)
sim.run(until=0.25 + secs)
