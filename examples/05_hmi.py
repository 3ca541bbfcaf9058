"""05_hmi: an HMI that drives a served program over TCP: Modbus (pymodbus) and ASCII (socket).

Start the controller in one terminal, then the HMI in another:

    motionvm serve --machine examples/05_hmi.toml examples/05_hmi.hmpl
    python examples/05_hmi.py 25.5 -12

For each target position given, the HMI writes it to holding registers 100-103
(system_dtest0, float64, high word first), writes the start request 1 to registers 0-1
(system_ltest0, int32), and waits until the program answers 2. Then it reads axis 0's
feedback position from input registers 1000-1003 and the outputs from coils 0-7, asks the
program's User ASCII agent for its `STATUS`, and asks the Native ASCII server for
`GetPosFb(0)` -- the same built-in a task calls. Ports default to the machine file's.
"""

from __future__ import annotations

import argparse
import socket
import struct
import sys
import time

from pymodbus.client import ModbusTcpClient


def to_words(value: float) -> list[int]:
    """A float64 as four Modbus registers, high word first."""
    return list(struct.unpack(">HHHH", struct.pack(">d", value)))


def from_words(words: list[int]) -> float:
    return struct.unpack(">d", struct.pack(">HHHH", *words))[0]


def ask(host: str, port: int, line: str, timeout: float = 5.0) -> str:
    """Send one line to an ASCII server and return its one-line reply."""
    with socket.create_connection((host, port), timeout=timeout) as sock:
        sock.sendall(line.encode("ascii") + b"\r\n")
        reply = b""
        while not reply.endswith(b"\r\n"):
            chunk = sock.recv(1024)
            if not chunk:
                break
            reply += chunk
    return reply.decode("ascii").rstrip("\r\n")


def run_job(modbus: ModbusTcpClient, target: float, timeout: float) -> bool:
    """Ask the program to move axis 0 to `target`; True once it has answered."""
    modbus.write_registers(100, to_words(target))  # system_dtest0
    modbus.write_registers(0, [0, 1])  # system_ltest0 = 1: start
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if modbus.read_holding_registers(0, count=2).registers == [0, 2]:
            return True
        time.sleep(0.05)
    return False


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("targets", nargs="*", type=float, default=[25.5], help="positions [mm]")
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--modbus-port", type=int, default=1502)
    p.add_argument("--native-port", type=int, default=3999)
    p.add_argument("--user-port", type=int, default=4000)
    p.add_argument("--timeout", type=float, default=10.0, help="per job [s]")
    args = p.parse_args(argv)

    modbus = ModbusTcpClient(args.host, port=args.modbus_port, timeout=5)
    if not modbus.connect():
        print(f"cannot reach the Modbus server at {args.host}:{args.modbus_port}", file=sys.stderr)
        return 1
    try:
        for target in args.targets:
            if not run_job(modbus, target, args.timeout):
                print(f"no answer for target {target}", file=sys.stderr)
                return 1
            pos = from_words(modbus.read_input_registers(1000, count=4).registers)
            coils = modbus.read_coils(0, count=8).bits[:8]
            print(f"target {target:g}: axis 0 at {pos:g} mm, outputs 1-8 {[int(b) for b in coils]}")
    finally:
        modbus.close()
    print("user ascii:", ask(args.host, args.user_port, "STATUS"))
    print("native ascii: GetPosFb(0) =", ask(args.host, args.native_port, "GetPosFb(0)"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
