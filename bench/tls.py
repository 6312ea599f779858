"""What Modbus/TCP Security costs: round trips per second with TLS beside plain Modbus/TCP, on 127.0.0.1.

Usage (from the repository root)::

    .venv/bin/python bench/tls.py                # about 15 seconds
    .venv/bin/python bench/tls.py --seconds 1 --repeat 1   # a smoke test

Two :class:`~modbus_edu.links.tcp.TcpServer` objects serve the same kind of slave, one plain, one with
``tls=`` (mutual TLS with the certificates of :func:`~modbus_edu.security.make_test_pki`, and the
course's role table deciding every request).  The same client - a :class:`~modbus_edu.master.Master`
over :func:`~modbus_edu.links.tcp.tcp_link`, plain or with ``tls=`` - reads 10 holding registers
(FC 3), one request at a time, for ``--seconds`` seconds.  Best of ``--repeat`` runs (the runs
alternate), and the ratio TLS / plain.  The handshake itself is timed apart (a new connection each
time).  Wall-clock time is used here and nowhere in the library's tests: speed belongs in ``bench/``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time

import modbus_edu as mb
from modbus_edu import security


def _rate(master: mb.Master, seconds: float) -> float:
    assert master.read_holding_registers(unit=1, address=0, count=10) == list(range(100, 110))
    done, start = 0, time.perf_counter()
    end = start + seconds
    while time.perf_counter() < end:
        master.read_holding_registers(unit=1, address=0, count=10)
        done += 1
    return done / (time.perf_counter() - start)


def _slave() -> mb.Slave:
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    slave.bank.holding_registers.write(0, list(range(100, 110)))
    return slave


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=2.0, help="length of one run (default 2)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per server, best kept (default 3)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        pki = security.make_test_pki(folder)
        client_tls = security.client_context(pki, role="viewer")
        with mb.TcpServer(_slave()) as plain, \
                mb.TcpServer(_slave(), tls=security.server_context(pki),
                             authorization=security.course_roles()) as secure:
            masters = {"plain": mb.Master(mb.tcp_link(*plain.address)),
                       "tls": mb.Master(mb.tcp_link(*secure.address, tls=client_tls))}
            best = {"plain": 0.0, "tls": 0.0}
            for _ in range(args.repeat):
                for name, master in masters.items():
                    best[name] = max(best[name], _rate(master, args.seconds))
            handshakes, start = 0, time.perf_counter()
            while time.perf_counter() - start < min(args.seconds, 2.0):
                mb.tcp_link(*secure.address, tls=client_tls).close()
                handshakes += 1
            handshake_ms = 1000 * (time.perf_counter() - start) / handshakes
            version = masters["tls"].link._sock.version()  # what the two sides agreed on
            for master in masters.values():
                master.link.close()
    print(f"FC3 x10 registers, one at a time, 127.0.0.1, best of {args.repeat} x {args.seconds:g} s")
    print(f"  plain Modbus/TCP        {best['plain']:8.0f} round trips/s")
    print(f"  Modbus/TCP Security     {best['tls']:8.0f} round trips/s   ({version})")
    print(f"  ratio TLS / plain       {best['tls'] / best['plain']:8.2f}")
    print(f"  TLS connection + handshake  {handshake_ms:.1f} ms each ({handshakes} made)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
