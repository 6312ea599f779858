"""Speed of the protocol core, ours against pymodbus 3.16, on the same inputs, in one run.

Usage (from the repository root)::

    .venv/bin/python bench/core.py              # the full run, about half a minute
    .venv/bin/python bench/core.py --quick      # fewer repeats, for a smoke test
    .venv/bin/python bench/core.py --repeat 9 --seconds 0.3

What is measured (best of N repeats, timeit-style: each repeat runs the statement in a loop for about
``--seconds`` seconds, the fastest repeat counts, because slower ones only measure interference):

``crc16 1 MiB``
    CRC-16/MODBUS over 1 MiB of seeded random bytes: ``modbus_edu.crc.crc16`` against
    ``FramerRTU.compute_CRC``.  In MB/s (1 MB = 10**6 bytes).
``RTU encode`` / ``TCP encode``
    From the same Python values (unit 1, ten register values, transaction id 1) to the bytes of an FC3
    response frame: build the PDU object and the frame, then encode.  pymodbus:
    ``ReadHoldingRegistersResponse(registers=..., dev_id=1, transaction_id=1)`` and
    ``FramerRTU/FramerSocket(...).buildFrame(pdu)``.  In frames/s.
``RTU decode`` / ``TCP decode``
    From the frame's bytes to a response object whose fields are read back (both libraries check the
    CRC and the lengths).  Ours: ``RtuFrame.decode(data, role="response")``; pymodbus:
    ``FramerRTU(DecodePDU(is_server=False)).handleFrame(data, 0, 0)``.  In frames/s.

Before timing, both sides are checked to produce (and read back) the same bytes and values, so the
table always compares equal work.  The ratio column is ours / pymodbus: above 1.0 we are faster.

No wall-clock time is used anywhere in the library; this script is the one place where speed is
measured, which is why it lives in ``bench/`` and not in ``tests/``.
"""

from __future__ import annotations

import argparse
import gc
import logging
import random
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import pymodbus
from pymodbus.framer import FramerRTU, FramerSocket
from pymodbus.pdu import DecodePDU
from pymodbus.pdu.register_message import ReadHoldingRegistersResponse as PmReadHoldingRegistersResponse

from modbus_edu.crc import crc16
from modbus_edu.framing import RtuFrame, TcpFrame
from modbus_edu.pdu import ReadHoldingRegistersResponse

SEED = 20240501


@dataclass
class Row:
    """One line of the table: a task, its unit, and the throughput of each library."""

    task: str
    unit: str
    ours: float
    theirs: float

    @property
    def ratio(self) -> float:
        return self.ours / self.theirs


def best_time(statement: Callable[[], object], *, repeat: int, seconds: float) -> float:
    """Seconds per call of ``statement``: the best of ``repeat`` timed loops of about ``seconds`` each."""
    # calibrate the loop count, like timeit.Timer.autorange
    number = 1
    while True:
        start = time.perf_counter()
        for _ in range(number):
            statement()
        elapsed = time.perf_counter() - start
        if elapsed >= seconds / 5:
            break
        number *= 2
    number = max(1, int(number * seconds / max(elapsed, 1e-9)))
    best = float("inf")
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeat):
            start = time.perf_counter()
            for _ in range(number):
                statement()
            best = min(best, (time.perf_counter() - start) / number)
    finally:
        if gc_was_enabled:
            gc.enable()
    return best


def bench_crc(repeat: int, seconds: float) -> Row:
    data = random.Random(SEED).randbytes(1 << 20)
    # same answer (pymodbus returns it byte-swapped); also warms up any lazily built table
    swapped = FramerRTU.compute_CRC(data)
    assert crc16(data) == ((swapped & 0xFF) << 8) | (swapped >> 8), "CRC disagrees with pymodbus"
    ours = best_time(lambda: crc16(data), repeat=repeat, seconds=seconds)
    theirs = best_time(lambda: FramerRTU.compute_CRC(data), repeat=repeat, seconds=seconds)
    return Row("crc16 over 1 MiB", "MB/s", len(data) / ours / 1e6, len(data) / theirs / 1e6)


def bench_frames(repeat: int, seconds: float) -> list[Row]:
    rng = random.Random(SEED)
    registers = [rng.randrange(65536) for _ in range(10)]
    unit, tid = 1, 1

    # --- RTU ---
    rtu_framer = FramerRTU(DecodePDU(is_server=False))

    def ours_rtu_encode() -> bytes:
        return RtuFrame(unit=unit, pdu=ReadHoldingRegistersResponse(registers=registers)).encode()

    def theirs_rtu_encode() -> bytes:
        pdu = PmReadHoldingRegistersResponse(registers=registers, dev_id=unit, transaction_id=tid)
        return rtu_framer.buildFrame(pdu)

    rtu = ours_rtu_encode()
    assert rtu == theirs_rtu_encode(), "RTU frames differ"
    assert len(rtu) == 1 + 1 + 1 + 20 + 2

    def ours_rtu_decode() -> object:
        return RtuFrame.decode(rtu, role="response")

    def theirs_rtu_decode() -> object:
        return rtu_framer.handleFrame(rtu, 0, 0)[1]

    frame = ours_rtu_decode()
    assert frame.unit == unit and list(frame.pdu.registers) == registers
    pm = theirs_rtu_decode()
    assert pm is not None and pm.dev_id == unit and list(pm.registers) == registers

    # --- TCP (MBAP) ---
    tcp_framer = FramerSocket(DecodePDU(is_server=False))

    def ours_tcp_encode() -> bytes:
        pdu = ReadHoldingRegistersResponse(registers=registers)
        return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()

    def theirs_tcp_encode() -> bytes:
        pdu = PmReadHoldingRegistersResponse(registers=registers, dev_id=unit, transaction_id=tid)
        return tcp_framer.buildFrame(pdu)

    tcp = ours_tcp_encode()
    assert tcp == theirs_tcp_encode(), "TCP frames differ"

    def ours_tcp_decode() -> object:
        return TcpFrame.decode(tcp, role="response")

    def theirs_tcp_decode() -> object:
        return tcp_framer.handleFrame(tcp, 0, 0)[1]

    frame = ours_tcp_decode()
    assert frame.transaction_id == tid and list(frame.pdu.registers) == registers
    pm = theirs_tcp_decode()
    assert pm is not None and pm.transaction_id == tid and list(pm.registers) == registers

    rows = []
    for task, ours, theirs in (
        ("RTU encode FC3 response, 10 registers", ours_rtu_encode, theirs_rtu_encode),
        ("RTU decode FC3 response, 10 registers", ours_rtu_decode, theirs_rtu_decode),
        ("TCP encode FC3 response, 10 registers", ours_tcp_encode, theirs_tcp_encode),
        ("TCP decode FC3 response, 10 registers", ours_tcp_decode, theirs_tcp_decode),
    ):
        t_ours = best_time(ours, repeat=repeat, seconds=seconds)
        t_theirs = best_time(theirs, repeat=repeat, seconds=seconds)
        rows.append(Row(task, "frames/s", 1 / t_ours, 1 / t_theirs))
    return rows


def format_table(rows: list[Row]) -> str:
    header = f"{'task':<40} {'unit':>9} {'modbus_edu':>12} {'pymodbus':>12} {'ratio':>7}"
    lines = [header, "-" * len(header)]
    for row in rows:
        lines.append(
            f"{row.task:<40} {row.unit:>9} {row.ours:>12,.1f} {row.theirs:>12,.1f} {row.ratio:>7.2f}"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="timed repeats per measurement (best counts)")
    parser.add_argument("--seconds", type=float, default=0.4, help="length of one timed repeat")
    parser.add_argument("--quick", action="store_true", help="3 repeats of 0.1 s (a smoke test)")
    args = parser.parse_args(argv)
    if args.quick:
        args.repeat, args.seconds = 3, 0.1
    # pymodbus logs through the logging module; make sure nothing is printed or formatted
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

    rows = [bench_crc(args.repeat, args.seconds), *bench_frames(args.repeat, args.seconds)]
    print(f"modbus_edu vs pymodbus {pymodbus.__version__}, Python {sys.version.split()[0]}, "
          f"best of {args.repeat} x ~{args.seconds} s; ratio = ours / pymodbus (> 1: we are faster)")
    print(format_table(rows))
    slower = [row.task for row in rows if row.ratio < 1.0]
    if slower:
        print("slower than pymodbus: " + "; ".join(slower))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
