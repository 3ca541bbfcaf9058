"""The simulated controller: its cycle and jump-ahead, the machine file, the scope
(registry, recorder, writers) and the real-time pacer. It imports no language."""
