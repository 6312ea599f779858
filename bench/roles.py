"""Speed of the roles on real sockets and on the virtual wire.

Usage (from the repository root)::

    .venv/bin/python bench/roles.py              # about 30 seconds
    .venv/bin/python bench/roles.py --quick      # shorter runs, for a smoke test
    .venv/bin/python bench/roles.py --seconds 3 --repeat 5

What is measured
----------------
(a) **Modbus/TCP servers**, on 127.0.0.1.  Our :class:`~modbus_edu.links.tcp.TcpServer` and pymodbus
    3.16's ``ModbusTcpServer`` (its own asyncio loop, in a thread), each serving a slave whose holding
    registers 0..9 hold known values, are driven by the **same client**, one request at a time: FC3,
    read 10 holding registers, for ``--seconds`` seconds.  Round trips per second, best of
    ``--repeat`` runs (runs alternate between the servers), and the ratio ours / pymodbus.  Two clients:
    pymodbus' own ``ModbusTcpClient`` (what a user would run; its own cost is in every round trip)
    and a bare socket client (pre-built request, reads the 29-byte answer: closer to the server's
    own speed).  Every answer is checked once before timing.

(b) **The virtual serial line** (:func:`~modbus_edu.links.loopback.loopback_serial`): a Master
    reading one holding register (FC3) from a Slave, RTU 8N1.

    * transactions per wall-clock second: how fast the simulation runs on this computer;
    * transactions per *virtual* second at 9600 and 115200 baud, next to the most the wire allows:
      ``1 / ((8 + 7) * char_time + 2 * t3.5)`` (an 8-byte request, a 7-byte response, and the 3.5
      character silence after each; t3.5 is 1.750 ms above 19200 baud).  The two must agree: the
      virtual wire times the line exactly.

Wall-clock time is used here and nowhere in the library's tests: speed belongs in ``bench/``.
"""

from __future__ import annotations

import argparse
import asyncio
import gc
import logging
import socket
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import pymodbus
from pymodbus.client import ModbusTcpClient
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import DataType, SimData, SimDevice

from modbus_edu.framing import TcpFrame
from modbus_edu.links.loopback import loopback_serial
from modbus_edu.links.tcp import TcpServer
from modbus_edu.links.wire import SerialTiming
from modbus_edu.master import Master
from modbus_edu.pdu import ReadHoldingRegistersRequest, ReadHoldingRegistersResponse
from modbus_edu.slave import Slave

HOST = "127.0.0.1"
VALUES = [1000 + i for i in range(10)]
COUNT = len(VALUES)

logging.getLogger("pymodbus").setLevel(logging.CRITICAL)


# --- the two servers -------------------------------------------------------------------------------------
class PymodbusServer:
    """pymodbus 3.16 ModbusTcpServer on its own asyncio loop in a background thread."""

    def __init__(self) -> None:
        regs = VALUES + [0] * (100 - COUNT)
        self.device = SimDevice(id=1, simdata=(
            [SimData(0, values=[False] * 100, datatype=DataType.BITS)],
            [SimData(0, values=[False] * 100, datatype=DataType.BITS)],
            [SimData(0, values=regs, datatype=DataType.REGISTERS)],
            [SimData(0, values=[0] * 100, datatype=DataType.REGISTERS)],
        ))
        self.address: tuple[str, int] = (HOST, 0)
        self._ready = threading.Event()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: ModbusTcpServer | None = None
        self._thread = threading.Thread(target=self._run, name="pymodbus server", daemon=True)

    def _run(self) -> None:
        async def main() -> None:
            self._server = ModbusTcpServer(self.device, address=(HOST, 0))
            await self._server.serve_forever(background=True)
            self.address = self._server.transport.sockets[0].getsockname()[:2]
            self._loop = asyncio.get_running_loop()
            self._ready.set()
            await self._server.serving

        asyncio.run(main())

    def __enter__(self) -> PymodbusServer:
        self._thread.start()
        if not self._ready.wait(10):
            raise RuntimeError("pymodbus server did not start")
        return self

    def __exit__(self, *exc_info: object) -> None:
        assert self._loop is not None and self._server is not None
        asyncio.run_coroutine_threadsafe(self._server.shutdown(), self._loop).result(10)
        self._thread.join(10)


def our_server() -> TcpServer:
    slave = Slave(unit=1)
    slave.bank.holding_registers.write(0, VALUES)
    return TcpServer(slave)


# --- the two clients ---------------------------------------------------------------------------------------
def pymodbus_client_loop(address: tuple[str, int]) -> tuple[Callable[[], None], Callable[[], None]]:
    client = ModbusTcpClient(address[0], port=address[1], timeout=5, retries=0)
    if not client.connect():
        raise RuntimeError(f"pymodbus client cannot connect to {address}")
    answer = client.read_holding_registers(0, count=COUNT, device_id=1)
    if answer.isError() or answer.registers != VALUES:
        raise RuntimeError(f"wrong answer from {address}: {answer}")

    def once() -> None:
        client.read_holding_registers(0, count=COUNT, device_id=1)

    return once, client.close


def socket_client_loop(address: tuple[str, int]) -> tuple[Callable[[], None], Callable[[], None]]:
    sock = socket.create_connection(address, timeout=5)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    request = TcpFrame(transaction_id=1, unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=COUNT))
    data = request.encode()
    size = 9 + 2 * COUNT
    sock.sendall(data)
    first = b""
    while len(first) < size:
        first += sock.recv(size - len(first))
    frame = TcpFrame.decode(first, role="response")
    if frame.transaction_id != 1 or frame.pdu != ReadHoldingRegistersResponse(registers=tuple(VALUES)):
        raise RuntimeError(f"wrong answer from {address}: {frame}")
    send, recv = sock.sendall, sock.recv

    def once() -> None:
        send(data)
        got = len(recv(size))
        while got < size:
            got += len(recv(size - got))

    return once, sock.close


def rate(once: Callable[[], None], seconds: float) -> float:
    """Calls of ``once`` per second over about ``seconds`` seconds (after a short warm-up)."""
    for _ in range(200):
        once()
    gc.collect()
    done = 0
    batch = 100
    start = time.perf_counter()
    deadline = start + seconds
    while True:
        for _ in range(batch):
            once()
        done += batch
        now = time.perf_counter()
        if now >= deadline:
            return done / (now - start)


# --- (a) --------------------------------------------------------------------------------------------------
@dataclass
class TcpRow:
    client: str
    ours: float
    theirs: float

    @property
    def ratio(self) -> float:
        return self.ours / self.theirs


def bench_tcp(seconds: float, repeat: int) -> list[TcpRow]:
    rows = []
    clients = (("pymodbus ModbusTcpClient", pymodbus_client_loop), ("bare socket client", socket_client_loop))
    with our_server() as ours, PymodbusServer() as theirs:
        for name, make in clients:
            best = {"ours": 0.0, "theirs": 0.0}
            for _ in range(repeat):
                for key, address in (("ours", ours.address), ("theirs", theirs.address)):
                    once, close = make(address)
                    try:
                        best[key] = max(best[key], rate(once, seconds))
                    finally:
                        close()
            rows.append(TcpRow(name, best["ours"], best["theirs"]))
    return rows


# --- (b) --------------------------------------------------------------------------------------------------
@dataclass
class SerialRow:
    baudrate: int
    wall_rate: float
    virtual_rate: float
    wire_max: float


def wire_maximum(baudrate: int) -> float:
    """FC3, one register, RTU 8N1: 8-byte request, 7-byte response, t3.5 after each."""
    timing = SerialTiming(baudrate=baudrate)
    return 1.0 / ((8 + 7) * timing.char_time + 2 * timing.t35)


def bench_serial(seconds: float, repeat: int, baudrates: tuple[int, ...]) -> list[SerialRow]:
    rows = []
    for baud in baudrates:
        best_wall = 0.0
        virtual = 0.0
        for _ in range(repeat):
            slave = Slave(unit=1)
            slave.bank.holding_registers[0] = 1234
            link = loopback_serial(slave, baudrate=baud)
            master = Master(link)
            if master.read_holding_registers(unit=1, address=0, count=1) != [1234]:
                raise RuntimeError("wrong answer on the virtual line")
            start_virtual = link.clock.now
            start_count = master.stats.valid_responses

            def once(master: Master = master) -> None:
                master.read_holding_registers(unit=1, address=0, count=1)

            best_wall = max(best_wall, rate(once, seconds))
            count = master.stats.valid_responses - start_count
            virtual = count / (link.clock.now - start_virtual)
            if master.stats.timeouts or master.stats.checksum_errors:
                raise RuntimeError(f"errors on the virtual line: {master.stats.summary()}")
        rows.append(SerialRow(baud, best_wall, virtual, wire_maximum(baud)))
    return rows


# --- report -------------------------------------------------------------------------------------------------
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=1.5, help="length of each timed run (default 1.5)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement, best counts (default 3)")
    parser.add_argument("--quick", action="store_true", help="0.5 s runs, 1 repeat")
    args = parser.parse_args(argv)
    seconds, repeat = (0.5, 1) if args.quick else (args.seconds, args.repeat)

    print(f"modbus_edu roles bench - Python {sys.version.split()[0]}, pymodbus {pymodbus.__version__}")
    print(f"best of {repeat} run(s) of {seconds:g} s each\n")

    print(f"(a) Modbus/TCP server round trips per second, FC3 read of {COUNT} registers, 127.0.0.1")
    header = f"    {'client':<26} {'TcpServer (ours)':>17} {'pymodbus server':>16} {'ratio':>7}"
    print(header)
    print("    " + "-" * (len(header) - 4))
    tcp_rows = bench_tcp(seconds, repeat)
    for row in tcp_rows:
        print(f"    {row.client:<26} {row.ours:>17,.0f} {row.theirs:>16,.0f} {row.ratio:>7.2f}")
    print("    ratio = ours / pymodbus; above 1.00 our server answers faster\n")

    print("(b) virtual serial line (loopback_serial), Master -> Slave, FC3 read of 1 register, RTU 8N1")
    header = (f"    {'baud':>7} {'transactions/s (wall)':>22} {'per virtual s':>14} "
              f"{'wire maximum':>13} {'virtual/max':>12}")
    print(header)
    print("    " + "-" * (len(header) - 4))
    serial_rows = bench_serial(seconds, repeat, (9600, 115200))
    for row in serial_rows:
        print(f"    {row.baudrate:>7} {row.wall_rate:>22,.0f} {row.virtual_rate:>14.2f} "
              f"{row.wire_max:>13.2f} {row.virtual_rate / row.wire_max:>12.4f}")
    print("    wire maximum = 1 / ((8 + 7) x char time + 2 x t3.5), t3.5 = 1.750 ms above 19200 baud")
    return 0


if __name__ == "__main__":
    sys.exit(main())
