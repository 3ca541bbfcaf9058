"""The controller's I/O and the plant behind it.

- `gpio.py`: the controller's general-purpose inputs and outputs, the E-stop input;
- `slaves.py`: the EtherCAT slaves (the drives, then digital and analog I/O modules);
- `analog.py`: the conversions of manual table 10.1.1;
- `config.py`: the machine file's `[io]`, `[[slave]]`, `[[wire]]`, `[[sensor]]` tables;
- `wiring.py`: wires and position sensors; `faults.py`: injected faults;
- `system.py`: the I/O system, a cycle client of the controller that owns all of it;
- `commands.py`: the functions of manual chapters 9 and 10 for any front end.
Position triggers belong here too, in a module of their own.
"""
