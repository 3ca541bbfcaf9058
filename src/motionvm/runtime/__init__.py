"""The run-time core every language shares: the clock, the cooperative task kernel, the
cycle-client and scope-source protocols, and the run-time fault types."""
