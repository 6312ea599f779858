"""How far past its timeout a Master waits when the peer never stops sending frames that are not its answer.

Usage (from the repository root)::

    .venv/bin/python bench/timeouts.py

A TCP peer on 127.0.0.1 streams responses with a foreign transaction id as fast as it can; the Master
(timeout 0.5 s) must give up at its deadline anyway.  Printed: the overshoot of each of 10 tries, in
milliseconds of wall-clock time, and the largest.  Target: under 50 ms.
"""

from __future__ import annotations

import socket
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import modbus_edu as mb  # noqa: E402

TIMEOUT = 0.5


def streaming_peer() -> tuple[socket.socket, threading.Event]:
    listener = socket.create_server(("127.0.0.1", 0))
    stop = threading.Event()
    foreign = mb.TcpFrame(transaction_id=0xBEEF, unit=1,
                          pdu=mb.ReadHoldingRegistersResponse(registers=[1])).encode() * 200

    def run() -> None:
        conn, _ = listener.accept()
        try:
            while not stop.is_set():
                conn.sendall(foreign)
        except OSError:
            pass
        finally:
            conn.close()

    threading.Thread(target=run, daemon=True).start()
    return listener, stop


def main() -> None:
    overshoots = []
    for _ in range(10):
        listener, stop = streaming_peer()
        with mb.tcp_link(*listener.getsockname()[:2]) as link:
            master = mb.Master(link, timeout=TIMEOUT)
            start = time.monotonic()
            try:
                master.read_holding_registers(unit=1, address=0, count=1)
            except mb.ModbusError:
                pass
            overshoots.append((time.monotonic() - start - TIMEOUT) * 1000)
            ignored = master.stats.mismatches
        stop.set()
        listener.close()
    print(f"timeout {TIMEOUT} s under a streaming peer ({ignored} foreign frames ignored in the last try)")
    print("overshoot, ms:", " ".join(f"{value:.1f}" for value in overshoots))
    print(f"largest: {max(overshoots):.1f} ms (target < 50 ms)")


if __name__ == "__main__":
    main()
