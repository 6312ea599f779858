"""Speed of the protocol core, ours against pymodbus 3.16, on the same inputs, in one run.

Usage (from the repository root)::

    .venv/bin/python bench/core.py              # the full run, about half a minute
    .venv/bin/python bench/core.py --quick      # fewer repeats, for a smoke test
    .venv/bin/python bench/core.py --repeat 31 --seconds 0.1   # on a busy machine: more, shorter repeats

What is measured (best of N repeats, timeit-style: each repeat runs the statement in a loop for about
``--seconds`` seconds, the fastest repeat counts, because slower ones only measure interference; the
repeats of the two libraries alternate, so load on the machine affects both alike):

``crc16 1 MiB``
    CRC-16/MODBUS over 1 MiB of seeded random bytes: ``modbus_edu.crc.crc16`` against
    ``FramerRTU.compute_CRC``.  In MB/s (1 MB = 10**6 bytes).
Frame rows, all on an FC3 (Read Holding Registers) response carrying 10 registers, unit 1, transaction
id 1 (TCP), in frames/s:

``RTU encode`` / ``TCP encode`` (object -> bytes)
    A response object that already exists becomes the frame's bytes.  Ours: ``frame.encode()`` of an
    ``RtuFrame`` / ``TcpFrame``; pymodbus: ``FramerRTU/FramerSocket(...).buildFrame(pdu)``.
``RTU decode`` / ``TCP decode`` (bytes -> object)
    The frame's bytes become a response object whose fields are read back (both libraries check the
    CRC and the lengths).  Ours: ``RtuFrame.decode(data, role="response")``; pymodbus:
    ``FramerRTU(DecodePDU(is_server=False)).handleFrame(data, 0, 0)``.
``RTU build + encode`` / ``TCP build + encode`` (values -> bytes)
    From the Python values (a list of ten ints) to the bytes: construct the objects, then encode.  Our
    constructors check every field (registers 0..65535, quantity 1..125, unit range, ...); pymodbus's
    ``ReadHoldingRegistersResponse(registers=..., dev_id=1, transaction_id=1)`` checks nothing, so
    this row shows what the teaching checks cost.

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


def _calibrate(statement: Callable[[], object], seconds: float) -> int:
    """How many calls take about ``seconds`` (like timeit.Timer.autorange)."""
    number = 1
    while True:
        start = time.perf_counter()
        for _ in range(number):
            statement()
        elapsed = time.perf_counter() - start
        if elapsed >= seconds / 5:
            return max(1, int(number * seconds / max(elapsed, 1e-9)))
        number *= 2


def _loop(statement: Callable[[], object], number: int) -> float:
    start = time.perf_counter()
    for _ in range(number):
        statement()
    return (time.perf_counter() - start) / number


def best_times(ours: Callable[[], object], theirs: Callable[[], object], *, repeat: int,
               seconds: float) -> tuple[float, float]:
    """Seconds per call of each statement: the best of ``repeat`` timed loops of about ``seconds`` each.

    The repeats alternate (ours, theirs, ours, theirs, ...), so a burst of load on the machine hits
    both sides alike instead of skewing the ratio.  The garbage collector is off while timing.
    """
    numbers = _calibrate(ours, seconds), _calibrate(theirs, seconds)
    best = [float("inf"), float("inf")]
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeat):
            for side, (statement, number) in enumerate(zip((ours, theirs), numbers)):
                best[side] = min(best[side], _loop(statement, number))
    finally:
        if gc_was_enabled:
            gc.enable()
    return best[0], best[1]


def bench_crc(repeat: int, seconds: float) -> Row:
    data = random.Random(SEED).randbytes(1 << 20)
    # same answer (pymodbus returns it byte-swapped); also warms up any lazily built table
    swapped = FramerRTU.compute_CRC(data)
    assert crc16(data) == ((swapped & 0xFF) << 8) | (swapped >> 8), "CRC disagrees with pymodbus"
    ours, theirs = best_times(lambda: crc16(data), lambda: FramerRTU.compute_CRC(data), repeat=repeat,
                              seconds=seconds)
    return Row("crc16 over 1 MiB", "MB/s", len(data) / ours / 1e6, len(data) / theirs / 1e6)


def bench_frames(repeat: int, seconds: float) -> list[Row]:
    """Frame rows: an FC3 response carrying 10 seeded random registers, unit 1, transaction id 1."""
    rng = random.Random(SEED)
    registers = [rng.randrange(65536) for _ in range(10)]
    unit, tid = 1, 1
    rtu_framer = FramerRTU(DecodePDU(is_server=False))
    tcp_framer = FramerSocket(DecodePDU(is_server=False))

    def theirs_pdu() -> PmReadHoldingRegistersResponse:
        return PmReadHoldingRegistersResponse(registers=registers, dev_id=unit, transaction_id=tid)

    ours_pdu = ReadHoldingRegistersResponse(registers=registers)
    ours_rtu = RtuFrame(unit=unit, pdu=ours_pdu)
    ours_tcp = TcpFrame(transaction_id=tid, unit=unit, pdu=ours_pdu)
    pm_rtu, pm_tcp = theirs_pdu(), theirs_pdu()

    def rtu_build() -> bytes:
        return RtuFrame(unit=unit, pdu=ReadHoldingRegistersResponse(registers=registers)).encode()

    def tcp_build() -> bytes:
        pdu = ReadHoldingRegistersResponse(registers=registers)
        return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()

    rtu, tcp = ours_rtu.encode(), ours_tcp.encode()
    # equal work: the same bytes out, the same values back
    assert len(rtu) == 1 + 1 + 1 + 20 + 2
    assert rtu == rtu_framer.buildFrame(pm_rtu) == rtu_build() == rtu_framer.buildFrame(theirs_pdu()), "RTU"
    assert tcp == tcp_framer.buildFrame(pm_tcp) == tcp_build() == tcp_framer.buildFrame(theirs_pdu()), "TCP"
    for data, ours_decoder, framer in ((rtu, RtuFrame, rtu_framer), (tcp, TcpFrame, tcp_framer)):
        frame = ours_decoder.decode(data, role="response")
        assert frame.unit == unit and list(frame.pdu.registers) == registers
        pm = framer.handleFrame(data, 0, 0)[1]
        assert pm is not None and pm.dev_id == unit and list(pm.registers) == registers

    cases: list[tuple[str, Callable[[], object], Callable[[], object]]] = [
        ("RTU encode (object -> bytes)", ours_rtu.encode, lambda: rtu_framer.buildFrame(pm_rtu)),
        ("RTU decode (bytes -> object)", lambda: RtuFrame.decode(rtu, role="response"),
         lambda: rtu_framer.handleFrame(rtu, 0, 0)[1]),
        ("TCP encode (object -> bytes)", ours_tcp.encode, lambda: tcp_framer.buildFrame(pm_tcp)),
        ("TCP decode (bytes -> object)", lambda: TcpFrame.decode(tcp, role="response"),
         lambda: tcp_framer.handleFrame(tcp, 0, 0)[1]),
        ("RTU build + encode (values -> bytes)", rtu_build, lambda: rtu_framer.buildFrame(theirs_pdu())),
        ("TCP build + encode (values -> bytes)", tcp_build, lambda: tcp_framer.buildFrame(theirs_pdu())),
    ]
    rows = []
    for task, ours, theirs in cases:
        t_ours, t_theirs = best_times(ours, theirs, repeat=repeat, seconds=seconds)
        rows.append(Row(task, "frames/s", 1 / t_ours, 1 / t_theirs))
    return rows


def bench_more_functions(repeat: int, seconds: float) -> list[Row]:
    """FC 23 (a read/write request writing 10 registers) and FC 43/14 (a basic identification response),
    RTU encode and decode, against pymodbus's classes for the same PDUs."""
    from pymodbus.pdu import mei_message as pm_mei
    from pymodbus.pdu import register_message as pm_reg

    from modbus_edu.pdu import ReadDeviceIdentificationResponse, ReadWriteMultipleRegistersRequest

    rng = random.Random(SEED)
    values = [rng.randrange(65536) for _ in range(10)]
    server = FramerRTU(DecodePDU(is_server=True))
    client = FramerRTU(DecodePDU(is_server=False))
    fc23 = RtuFrame(1, ReadWriteMultipleRegistersRequest(3, 6, 14, values))
    pm23 = pm_reg.ReadWriteMultipleRegistersRequest(read_address=3, read_count=6, write_address=14,
                                                   write_registers=values, dev_id=1)
    objects = ((0, b"modbus_edu"), (1, b"simulated slave"), (2, b"1.0"))
    fc43 = RtuFrame(1, ReadDeviceIdentificationResponse(1, 0x83, False, 0, objects))
    pm43 = pm_mei.ReadDeviceInformationResponse(read_code=1, information=dict(objects), dev_id=1)
    rtu23, rtu43 = fc23.encode(), fc43.encode()
    assert rtu23 == server.buildFrame(pm23), "FC 23"
    assert client.handleFrame(rtu43, 0, 0)[1].information == dict(objects), "FC 43"
    cases = [
        ("FC23 RTU encode (object -> bytes)", fc23.encode, lambda: server.buildFrame(pm23)),
        ("FC23 RTU decode (bytes -> object)", lambda: RtuFrame.decode(rtu23, role="request"),
         lambda: server.handleFrame(rtu23, 0, 0)[1]),
        ("FC43/14 RTU encode (object -> bytes)", fc43.encode, lambda: client.buildFrame(pm43)),
        ("FC43/14 RTU decode (bytes -> object)", lambda: RtuFrame.decode(rtu43, role="response"),
         lambda: client.handleFrame(rtu43, 0, 0)[1]),
    ]
    rows = []
    for task, ours, theirs in cases:
        t_ours, t_theirs = best_times(ours, theirs, repeat=repeat, seconds=seconds)
        rows.append(Row(task, "frames/s", 1 / t_ours, 1 / t_theirs))
    return rows


def format_table(rows: list[Row]) -> str:
    header = f"{'task':<38} {'unit':>9} {'modbus_edu':>12} {'pymodbus':>12} {'ratio':>7}"
    lines = [header, "-" * len(header)]
    for row in rows:
        lines.append(
            f"{row.task:<38} {row.unit:>9} {row.ours:>12,.1f} {row.theirs:>12,.1f} {row.ratio:>7.2f}"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15, help="timed repeats per measurement (best counts)")
    parser.add_argument("--seconds", type=float, default=0.15, help="length of one timed repeat")
    parser.add_argument("--quick", action="store_true", help="3 repeats of 0.1 s (a smoke test)")
    args = parser.parse_args(argv)
    if args.quick:
        args.repeat, args.seconds = 3, 0.1
    # pymodbus logs through the logging module; make sure nothing is printed or formatted
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

    rows = [bench_crc(args.repeat, args.seconds), *bench_frames(args.repeat, args.seconds),
            *bench_more_functions(args.repeat, args.seconds)]
    print(f"modbus_edu vs pymodbus {pymodbus.__version__}, Python {sys.version.split()[0]}, "
          f"best of {args.repeat} x ~{args.seconds} s; ratio = ours / pymodbus (> 1: we are faster)")
    print("frames: an FC3 response with 10 registers, unit 1")
    print(format_table(rows))
    targets = [row for row in rows if "build" not in row.task]
    slower = [row.task for row in targets if row.ratio < 1.0]
    print("targets (every ratio >= 1.0): crc16 and every object <-> bytes row: "
          + ("met" if not slower else "missed: " + "; ".join(slower)))
    print("the 'build + encode' rows are extra: they add object construction, where our constructors "
          "check every field and pymodbus's check none")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
