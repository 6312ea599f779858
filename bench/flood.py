"""What a TcpServer holds for clients that flood it, and what a bystander waits meanwhile.

Usage (from the repository root)::

    .venv/bin/python bench/flood.py

For each framing (Modbus/TCP, RTU and ASCII over TCP): ten clients send FC 3 requests back to back and
never read an answer, for two seconds or until TCP's flow control stops them; a bystander client asks
one request meanwhile.  Printed: the bytes the clients got into the kernel, the bytes the server holds
for them (``TcpServer.buffered_bytes``, bounded per connection by ``MAX_BUFFERED_PER_CONNECTION``), and
the bystander's wait.
"""

from __future__ import annotations

import socket
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import modbus_edu as mb  # noqa: E402
from modbus_edu.links.tcp import TcpServer  # noqa: E402

CLIENTS = 10


def request(framing: str) -> bytes:
    pdu = mb.ReadHoldingRegistersRequest(address=0, count=10)
    if framing == "tcp":
        return mb.TcpFrame(transaction_id=1, unit=1, pdu=pdu).encode()
    return (mb.RtuFrame if framing == "rtu" else mb.AsciiFrame)(unit=1, pdu=pdu).encode()


def flood(sock: socket.socket, data: bytes, seconds: float) -> int:
    sock.setblocking(False)
    sent, end, stalled = 0, time.monotonic() + seconds, None
    while time.monotonic() < end:
        try:
            sent += sock.send(data)
            stalled = None
        except BlockingIOError:
            stalled = stalled or time.monotonic()
            if time.monotonic() - stalled > 0.3:
                break
            time.sleep(0.005)
    return sent


def main() -> int:
    print(f"{CLIENTS} clients pipelining FC 3 without reading; bound per connection: "
          f"{TcpServer.MAX_BUFFERED_PER_CONNECTION:,} bytes")
    print(f"{'framing':<8} {'sent by the clients':>20} {'held by the server':>19} {'bystander waited':>17}")
    for framing in ("tcp", "rtu", "ascii"):
        with TcpServer(mb.Slave(unit=1), framing=framing) as server:
            port = server.address[1]
            clients = [socket.create_connection(("127.0.0.1", port)) for _ in range(CLIENTS)]
            bystander = socket.create_connection(("127.0.0.1", port), timeout=5)
            try:
                sent = sum(flood(sock, request(framing) * 2000, 2.0) for sock in clients)
                held = server.buffered_bytes
                start = time.monotonic()
                bystander.sendall(request(framing))
                bystander.recv(256)
                waited = (time.monotonic() - start) * 1000
            finally:
                for sock in [*clients, bystander]:
                    sock.close()
        print(f"{framing:<8} {sent:>20,} {held:>19,} {waited:>14.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
