"""How far past its timeout a Master waits when the peer never stops sending what is not its answer.

Usage (from the repository root)::

    .venv/bin/python bench/timeouts.py            # 5 tries per case
    .venv/bin/python bench/timeouts.py --tries 10

A peer on 127.0.0.1 streams, as fast as loopback carries it, one of: 0xFF junk or responses with a
foreign transaction id over Modbus/TCP (``tcp_link``); 0xFF junk, another unit's RTU frames or a run of
':' over a serial line carried by TCP (``serial_link("socket://...")``).  The Master (timeout 0.5 s) must
give up at its deadline anyway.  Printed per case: the worst and median overshoot in milliseconds of
wall-clock time, and whether the request after the flood ends is answered at once (the stale backlog is
dropped, not waited behind).  Target: overshoot under 50 ms.
"""

from __future__ import annotations

import argparse
import socket
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import modbus_edu as mb  # noqa: E402

TIMEOUT = 0.5
FOREIGN_TCP = mb.TcpFrame(transaction_id=0xBEEF, unit=1,
                          pdu=mb.ReadHoldingRegistersResponse(registers=[1])).encode()
OTHER_UNIT_RTU = mb.RtuFrame(unit=7, pdu=mb.ReadHoldingRegistersResponse(registers=[2000])).encode()
CASES = [
    ("Modbus/TCP, 0xFF junk", "tcp", b"\xff"),
    ("Modbus/TCP, foreign transaction ids", "tcp", FOREIGN_TCP),
    ("socket:// RTU, 0xFF junk", "rtu", b"\xff"),
    ("socket:// RTU, another unit's frames", "rtu", OTHER_UNIT_RTU),
    ("socket:// ASCII, a run of ':'", "ascii", b":"),
]


class Peer:
    """Streams ``payload`` to each connection for ``seconds``, then answers each request with 1234."""

    def __init__(self, payload: bytes, seconds: float, mode: str) -> None:
        self.payload = payload * max(1, 65536 // len(payload))
        self.seconds, self.mode = seconds, mode
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.stop = threading.Event()
        threading.Thread(target=self._accept, daemon=True).start()

    def _accept(self) -> None:
        while not self.stop.is_set():
            try:
                conn, _ = self.listener.accept()
            except OSError:
                return
            threading.Thread(target=self._serve, args=(conn,), daemon=True).start()

    def _answer(self, request: bytes) -> bytes:
        pdu = mb.ReadHoldingRegistersResponse(registers=[1234])
        if self.mode == "tcp":
            tid = int.from_bytes(request[:2], "big")
            return mb.TcpFrame(transaction_id=tid, unit=1, pdu=pdu).encode()
        frame = mb.RtuFrame if self.mode == "rtu" else mb.AsciiFrame
        return frame(unit=1, pdu=pdu).encode()

    def _serve(self, conn: socket.socket) -> None:
        end = time.monotonic() + self.seconds
        conn.settimeout(0.1)
        try:
            while not self.stop.is_set() and time.monotonic() < end:
                try:
                    conn.send(self.payload)
                except TimeoutError:
                    continue
            conn.settimeout(5.0)
            while not self.stop.is_set():
                request = conn.recv(4096)
                if not request:
                    return
                conn.sendall(self._answer(request))
        except OSError:
            pass
        finally:
            conn.close()

    def close(self) -> None:
        self.stop.set()
        self.listener.close()


def _link(mode: str, port: int):
    if mode == "tcp":
        return mb.tcp_link("127.0.0.1", port)
    return mb.serial_link(f"socket://127.0.0.1:{port}", mode=mode)


def run_case(mode: str, payload: bytes, tries: int) -> tuple[list[float], float | None]:
    """Overshoots (ms) of ``tries`` timed-out reads during a flood, and the time (ms) of the first read
    after the flood ends (None if it was not answered)."""
    flood = 0.6 + tries * (TIMEOUT + 0.2)
    peer = Peer(payload, flood, mode)
    overshoots: list[float] = []
    try:
        with _link(mode, peer.port) as link:
            master = mb.Master(link, timeout=TIMEOUT)
            for _ in range(tries):
                start = time.monotonic()
                try:
                    master.read_holding_registers(unit=1, address=0, count=1)
                except mb.ModbusError:
                    pass
                overshoots.append((time.monotonic() - start - TIMEOUT) * 1000)
            time.sleep(max(0.0, flood - tries * TIMEOUT) + 0.3)  # the flood ends; its backlog may remain
            start = time.monotonic()
            try:
                answered = master.read_holding_registers(unit=1, address=0, count=1) == [1234]
            except mb.ModbusError:
                answered = False
            after = (time.monotonic() - start) * 1000 if answered else None
    finally:
        peer.close()
    return overshoots, after


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tries", type=int, default=5, help="timed-out reads per case (default 5)")
    args = parser.parse_args(argv)
    print(f"Master timeout {TIMEOUT * 1000:.0f} ms; overshoot past it while the peer streams, "
          f"{args.tries} tries")
    print(f"{'case':<38} {'worst':>9} {'median':>9}   next request after the flood")
    for name, mode, payload in CASES:
        overshoots, after = run_case(mode, payload, args.tries)
        answer = f"answered in {after:.1f} ms" if after is not None else "NOT answered"
        print(f"{name:<38} {max(overshoots):>6.1f} ms {statistics.median(overshoots):>6.1f} ms   {answer}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
