"""A live client's worst wait behind a dead unit at the gateway, in wall-clock time.

Usage (from the repository root)::

    .venv/bin/python bench/gateway.py [seconds]

A serial device server (raw TCP, :class:`~modbus_edu.links.serial.TcpSerialPort`) has unit 1 on its
line; a :class:`~modbus_edu.gateway.TcpGateway` reaches it over ``socket://`` with a 0.25 s timeout.
Eight clients keep asking unit 5, which nobody answers; one client asks unit 1 every 20 ms. Printed: the
live client's requests, its median and worst wait, and the dead clients' answers.  Target: the worst
wait under one bus timeout plus its own transaction (~0.3 s); with the bus on the server's only thread
it was 6.1 s.
"""

from __future__ import annotations

import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import modbus_edu as mb  # noqa: E402

TIMEOUT = 0.25
DEAD_CLIENTS = 8


def measure(seconds: float = 10.0) -> tuple[list[float], int]:
    """The live client's waits (s), and how many answers the dead unit's clients got."""
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    device = mb.SerialServer(slave, mb.TcpSerialPort("127.0.0.1", 0), mode="rtu").start()
    link = mb.serial_link(f"socket://127.0.0.1:{device.port.address[1]}", baudrate=9600)
    waits: list[float] = []
    dead_answers = [0]
    end = time.monotonic() + seconds
    try:
        with mb.TcpGateway(link, timeout=TIMEOUT) as gw:

            def dead() -> None:
                with mb.tcp_link(*gw.address) as tcp:
                    master = mb.Master(tcp, timeout=30)
                    while time.monotonic() < end:
                        try:
                            master.read_holding_registers(unit=5, address=0, count=1)
                        except mb.ModbusExceptionError:
                            dead_answers[0] += 1

            def live() -> None:
                with mb.tcp_link(*gw.address) as tcp:
                    master = mb.Master(tcp, timeout=30)
                    time.sleep(0.5)  # the dead unit's queue fills first
                    while time.monotonic() < end:
                        start = time.monotonic()
                        master.read_holding_registers(unit=1, address=0, count=1)
                        waits.append(time.monotonic() - start)
                        time.sleep(0.02)

            threads = [threading.Thread(target=dead) for _ in range(DEAD_CLIENTS)]
            threads.append(threading.Thread(target=live))
            for t in threads:
                t.start()
            for t in threads:
                t.join()
    finally:
        link.close()
        device.close()
    return waits, dead_answers[0]


def main() -> None:
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    waits, dead = measure(seconds)
    print(f"{DEAD_CLIENTS} clients asking a silent unit at a {TIMEOUT} s timeout, one asking a live unit, "
          f"{seconds:g} s:")
    print(f"  live client: {len(waits)} requests, median wait {statistics.median(waits) * 1000:.1f} ms, "
          f"worst {max(waits) * 1000:.1f} ms")
    print(f"  dead unit's clients: {dead} answers 0B")


if __name__ == "__main__":
    main()
