"""The drives on the simulated EtherCAT bus: the CiA 402 drive and its object dictionary,
the mechanics behind it (ideal tracking, a servo loop) and its sensors (limit and home
switches, index pulse, touch probes)."""
