"""Motion: axes and their profile generator, PVT, gear, gantry, homing and touch probes,
stepped by the motion kernel each cycle; `commands/` holds the semantics of the axis
built-ins in the manual's units and error codes, for any front end."""
