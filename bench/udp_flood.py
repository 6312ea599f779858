"""Whether a Modbus/UDP master is still served while another source floods the server.

Usage (from the repository root)::

    .venv/bin/python bench/udp_flood.py                    # the full scenario, about 8 seconds
    .venv/bin/python bench/udp_flood.py --datagrams 30000 --seconds 1   # a smoke test

Two floods, each from another UDP port of the same host, in a process of its own, paced to
``--datagrams`` datagrams in ``--seconds`` seconds (300,000 in 3 s by default): **junk** (12 bytes that
are no MBAP frame) and **valid requests** (FC 3 of 10 registers to the served unit).  Meanwhile a
legitimate master (:func:`~modbus_edu.links.udp.udp_link`, ``Master(link, timeout=0.3, retries=2)``)
reads 10 holding registers every 0.25 s.  Printed for each flood: the reads answered within 1 s out of
the reads made, the slowest answered read, the datagrams the flood got out of its socket, and the
server's counters (``requests``, ``bad_datagrams``, ``dropped_datagrams``).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import modbus_edu as mb  # noqa: E402

#: The flooding process: sends ``count`` copies of a datagram to (host, port) in ``seconds``, paced per
#: thousand, stops at ``seconds`` even if short of ``count`` (a busy machine sends fewer), and prints how
#: many the kernel accepted (a full send buffer refuses a few).
FLOODER = """
import socket, sys, time
host, port, count, seconds, payload = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), \
    bytes.fromhex(sys.argv[5])
sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
sock.setblocking(False)
sent, start = 0, time.monotonic()
for i in range(count):
    try:
        sock.sendto(payload, (host, port))
        sent += 1
    except OSError:
        pass
    if i % 1000 == 999:
        ahead = start + seconds * (i + 1) / count - time.monotonic()
        if time.monotonic() > start + seconds:
            break
        if ahead > 0:
            time.sleep(ahead)
print(sent)
"""

JUNK = bytes(range(12))


def valid_request() -> bytes:
    """An FC 3 request of 10 registers to unit 1, as the flood sends it."""
    pdu = mb.ReadHoldingRegistersRequest(address=0, count=10)
    return mb.TcpFrame(transaction_id=7, unit=1, pdu=pdu).encode()


def run(payload: bytes, datagrams: int, seconds: float, every: float = 0.25) -> dict:
    """Serve one flood of ``payload`` and read every ``every`` seconds meanwhile; the figures of the run.

    tests/test_udp.py runs it smaller: the test and the benchmark measure the same thing."""
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    slave.bank.holding_registers.write(0, list(range(100, 110)))
    with mb.UdpServer(slave) as server:
        host, port = server.address
        flood = subprocess.Popen(
            [sys.executable, "-c", FLOODER, host, str(port), str(datagrams), str(seconds), payload.hex()],
            stdout=subprocess.PIPE, text=True)
        answered = made = 0
        slowest = 0.0
        with mb.udp_link(host, port) as link:
            master = mb.Master(link, timeout=0.3, retries=2)
            time.sleep(0.2)  # the flood is under way
            end = time.monotonic() + seconds - 0.4
            while time.monotonic() < end:
                made += 1
                start = time.monotonic()
                try:
                    registers = master.read_holding_registers(unit=1, address=0, count=10)
                except mb.ModbusError:
                    registers = None
                took = time.monotonic() - start
                if registers == list(range(100, 110)) and took <= 1.0:
                    answered += 1
                    slowest = max(slowest, took)
                time.sleep(max(0.0, every - took))
        out, _ = flood.communicate(timeout=seconds + 30)
        return {"answered": answered, "made": made, "slowest": slowest, "sent": int(out),
                "requests": server.requests, "bad": server.bad_datagrams,
                "dropped": getattr(server, "dropped_datagrams", 0)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--datagrams", type=int, default=300_000, help="datagrams per flood (default 300000)")
    parser.add_argument("--seconds", type=float, default=3.0, help="length of each flood (default 3)")
    args = parser.parse_args(argv)
    print(f"flood of {args.datagrams:,} datagrams in {args.seconds:g} s from another port; "
          "the master: timeout 0.3 s, 2 retries, a read every 0.25 s")
    print(f"{'flood':<16} {'answered <= 1 s':>16} {'slowest':>9} {'flood sent':>11} {'requests':>9} "
          f"{'bad':>8} {'dropped':>8}")
    for name, payload in (("junk", JUNK), ("valid requests", valid_request())):
        r = run(payload, args.datagrams, args.seconds)
        share = f"{r['answered']}/{r['made']} ({100 * r['answered'] / max(r['made'], 1):.0f}%)"
        print(f"{name:<16} {share:>16} {r['slowest'] * 1000:>6.0f} ms {r['sent']:>11,} {r['requests']:>9,} "
              f"{r['bad']:>8,} {r['dropped']:>8,}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
