"""Speed of the roles on real sockets and on the virtual wire.

Usage (from the repository root)::

    .venv/bin/python bench/roles.py              # about 30 seconds
    .venv/bin/python bench/roles.py --quick      # shorter runs, for a smoke test
    .venv/bin/python bench/roles.py --seconds 3 --repeat 5
    .venv/bin/python bench/roles.py --servers-only   # (a) and (c) alone

What is measured
----------------
(a) **Modbus/TCP servers**, on 127.0.0.1, each in a process of its own: our
    :class:`~modbus_edu.links.tcp.TcpServer`, pymodbus 3.16's ``ModbusTcpServer`` (its asyncio loop),
    each serving a slave whose holding registers 0..9 hold known values, and a bare ``selectors`` loop
    that answers every request with one fixed frame (what no Python server can beat).  One and four
    raw-socket client processes (a pre-built request, the 29-byte answer read back, one request at a
    time each) drive each server for ``--seconds`` seconds; round trips per second, added over the
    clients, best of ``--repeat`` runs, and the ratios to pymodbus and to the bare loop.  Every
    client checks one answer before timing.  Beside them, each server's CPU time per request (user +
    system, read from ``/proc/PID/stat`` before and after a run, divided by every request of the run):
    less sensitive to the machine's load than the rates.  The three servers take turns within each
    repeat, so that a change of load touches them alike.

(b) **The virtual serial line** (:func:`~modbus_edu.links.loopback.loopback_serial`): a Master
    reading one holding register (FC3) from a Slave, RTU 8N1.

    * transactions per wall-clock second: how fast the simulation runs on this computer;
    * transactions per *virtual* second at 9600 and 115200 baud, next to the most the wire allows:
      ``1 / ((8 + 7) * char_time + 2 * t3.5)`` (an 8-byte request, a 7-byte response, and the 3.5
      character silence after each; t3.5 is 1.750 ms above 19200 baud).  The two must agree: the
      virtual wire times the line exactly.

(c) **Reading a slave's full traffic log** (1000 entries, half of them answers of the fast path, whose
    notes are written when the log is read): milliseconds of CPU time for ``to_text()``, every note
    new.  Target: under 10 ms.

Wall-clock time is used here and nowhere in the library's tests: speed belongs in ``bench/``.
"""

from __future__ import annotations

import argparse
import asyncio
import gc
import logging
import os
import socket
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import pymodbus
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


# --- the client ---------------------------------------------------------------------------------------
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
SERVERS = ("TcpServer (ours)", "pymodbus 3.16", "bare selectors loop")
#: The fixed answer the bare loop sends: what a Python server that does no Modbus work at all can do.
_FIXED_ANSWER = TcpFrame(transaction_id=1, unit=1, pdu=ReadHoldingRegistersResponse(registers=tuple(VALUES))
                         ).encode()


def _bare_loop(listener: socket.socket) -> None:
    """A selectors loop that answers every 12-byte request with the same 29-byte frame: no parsing, no
    data bank, no checks.  The ceiling for a Python server on this machine."""
    import selectors

    selector = selectors.DefaultSelector()
    listener.setblocking(False)
    selector.register(listener, selectors.EVENT_READ)
    pending: dict[socket.socket, int] = {}
    while True:
        for key, _ in selector.select():
            sock = key.fileobj
            if sock is listener:
                conn, _ = listener.accept()
                conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
                conn.setblocking(False)
                pending[conn] = 0
                selector.register(conn, selectors.EVENT_READ)
                continue
            data = sock.recv(65536)
            if not data:
                selector.unregister(sock)
                sock.close()
                continue
            got = pending[sock] + len(data)
            pending[sock] = got % 12
            sock.sendall(_FIXED_ANSWER * (got // 12))


def _serve_in_process(kind: str, ports) -> None:
    """The body of a server process: serve ``kind`` on 127.0.0.1 until terminated."""
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)
    if kind == SERVERS[0]:
        server = our_server()
        server._bind()
        ports.put(server.address[1])
        server.serve_forever()
    elif kind == SERVERS[1]:
        async def main() -> None:
            device = PymodbusServer().device
            server = ModbusTcpServer(device, address=(HOST, 0))
            await server.serve_forever(background=True)
            ports.put(server.transport.sockets[0].getsockname()[1])
            await server.serving

        asyncio.run(main())
    else:
        listener = socket.create_server((HOST, 0))
        ports.put(listener.getsockname()[1])
        _bare_loop(listener)


def _client_in_process(port: int, seconds: float, start_at: float, results) -> None:
    """A raw-socket client process: FC3 round trips, one at a time, counted from ``start_at``.  Puts
    ``(rate, every request it sent)``: the second, warm-up included, divides the server's CPU time."""
    once, close = socket_client_loop((HOST, port))
    for _ in range(200):
        once()
    while time.time() < start_at:
        time.sleep(0.001)
    done, end = 0, start_at + seconds
    while time.time() < end:
        for _ in range(50):
            once()
        done += 50
    close()
    results.put((done / (time.time() - start_at), done + 201))


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of process ``pid`` so far, from ``/proc/PID/stat`` (fields 14 and 15)."""
    with open(f"/proc/{pid}/stat") as stat:
        fields = stat.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


@dataclass
class ServerRun:
    """The best round trips per second a server reached, and the least CPU it spent per request."""

    rate: float = 0.0
    cpu_per_request: float = float("inf")


def bench_servers(seconds: float, repeat: int, clients: tuple[int, ...] = (1, 4)
                  ) -> dict[str, dict[int, ServerRun]]:
    """Round trips per second of each server, each in its own process, driven by ``n`` raw-socket client
    processes at once (their rates added), and the server's CPU time per request (``/proc``); best of
    ``repeat`` runs.  The servers take turns within each repeat, so that a change in the machine's load
    touches all three alike and the ratios of one run stay fair."""
    import multiprocessing

    context = multiprocessing.get_context("fork")
    table: dict[str, dict[int, ServerRun]] = {kind: {n: ServerRun() for n in clients} for kind in SERVERS}
    servers, ports = {}, {}
    try:
        for kind in SERVERS:
            queue = context.Queue()
            servers[kind] = context.Process(target=_serve_in_process, args=(kind, queue), daemon=True)
            servers[kind].start()
            ports[kind] = queue.get(timeout=20)
        for _ in range(repeat):
            for n in clients:
                for kind in SERVERS:
                    results = context.Queue()
                    start_at = time.time() + 1.0
                    args = (ports[kind], seconds, start_at, results)
                    workers = [context.Process(target=_client_in_process, args=args) for _ in range(n)]
                    cpu_before = cpu_seconds(servers[kind].pid)
                    for worker in workers:
                        worker.start()
                    answers = [results.get(timeout=seconds + 30) for _ in workers]
                    for worker in workers:
                        worker.join(10)
                    cpu = cpu_seconds(servers[kind].pid) - cpu_before
                    best = table[kind][n]
                    best.rate = max(best.rate, sum(rate for rate, _ in answers))
                    best.cpu_per_request = min(best.cpu_per_request, cpu / sum(done for _, done in answers))
    finally:
        for server in servers.values():
            server.terminate()
            server.join(10)
    return table


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


# --- (c) --------------------------------------------------------------------------------------------------
def bench_log_read(repeat: int) -> float:
    """Milliseconds of CPU time to read a slave's full traffic log (1000 entries: 500 Modbus/TCP FC3 reads
    of 10 registers answered on the fast path, each answer different) as text, its notes written then;
    best of ``repeat``.  The worst case: no note is remembered from an earlier read."""
    best = float("inf")
    for run in range(repeat):
        slave = Slave(unit=1)
        table = slave.bank.holding_registers
        for tid in range(500):  # values never seen before: no note is remembered
            table.write(0, [(run * 5003 + tid * 10 + i) & 0xFFFF for i in range(COUNT)])
            request = TcpFrame(transaction_id=tid, unit=1, pdu=ReadHoldingRegistersRequest(address=0,
                                                                                           count=COUNT))
            slave.handle(request.encode(), "tcp")
        start = time.process_time()
        text = slave.log.to_text()
        best = min(best, time.process_time() - start)
        if len(slave.log) != 1000 or f"registers [{run * 5003 + 4990}, " not in text:
            raise RuntimeError("the log does not hold what the slave answered")
    return best * 1e3


# --- report -------------------------------------------------------------------------------------------------
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=1.5, help="length of each timed run (default 1.5)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per measurement, best counts (default 3)")
    parser.add_argument("--quick", action="store_true", help="0.5 s runs, 1 repeat")
    parser.add_argument("--servers-only", action="store_true", help="the servers (a) and the log (c) only")
    args = parser.parse_args(argv)
    seconds, repeat = (0.5, 1) if args.quick else (args.seconds, args.repeat)

    print(f"modbus_edu roles bench - Python {sys.version.split()[0]}, pymodbus {pymodbus.__version__}")
    print(f"best of {repeat} run(s) of {seconds:g} s each\n")

    print(f"(a) Modbus/TCP servers, each in its own process: FC3 read of {COUNT} registers, round trips")
    print("    per second from raw-socket client processes on 127.0.0.1 (one request at a time each),")
    print("    and the server's CPU time per request (user + system, from /proc)")
    header = (f"    {'server':<22} {'1 client':>10} {'4 clients':>10} {'vs pymodbus':>12} "
              f"{'vs bare loop':>13} {'CPU us/request':>15}")
    print(header)
    print("    " + "-" * (len(header) - 4))
    table = bench_servers(seconds, repeat)
    theirs, bare = table[SERVERS[1]], table[SERVERS[2]]
    for kind in SERVERS:
        row = table[kind]
        versus = " / ".join(f"{row[n].rate / theirs[n].rate:.2f}" for n in (1, 4))
        ceiling = " / ".join(f"{row[n].rate / bare[n].rate:.2f}" for n in (1, 4))
        cpu = " / ".join(f"{row[n].cpu_per_request * 1e6:.1f}" for n in (1, 4))
        print(f"    {kind:<22} {row[1].rate:>10,.0f} {row[4].rate:>10,.0f} {versus:>12} {ceiling:>13} "
              f"{cpu:>15}")
    print("    ratios and CPU for 1 / 4 clients; the bare loop answers a fixed frame and does no Modbus at")
    print("    all; the servers take turns in each run, so a change of the machine's load touches all")
    print("    three alike\n")

    print(f"(c) reading a slave's full traffic log (1000 entries, 500 fast-path answers, every note new): "
          f"{bench_log_read(repeat):.1f} ms of CPU (target: under 10 ms)\n")
    if args.servers_only:
        return 0
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
