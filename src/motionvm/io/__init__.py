"""The controller's I/O: its general-purpose digital inputs and outputs (`gpio.py`).

EtherCAT I/O slaves (digital and analog), position triggers, and the plant wiring and
sensors behind them belong here too, each in a module of its own.
"""
