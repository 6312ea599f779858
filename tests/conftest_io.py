"""Helpers for the tests that use real sockets: pymodbus 3.16 peers run in a background thread.

Not a conftest (pytest does not load it by itself): the I/O tests import it.  Everything listens on
127.0.0.1 with a port chosen by the system (port 0), and every server started here is shut down by the
context manager that started it.
"""

from __future__ import annotations

import asyncio
import logging
import socket
import threading
from collections.abc import Iterator
from contextlib import contextmanager

from pymodbus.constants import ExcCodes
from pymodbus.framer import FramerType
from pymodbus.server import ModbusTcpServer, ModbusTlsServer
from pymodbus.simulator import DataType, SimData, SimDevice

HOST = "127.0.0.1"
#: Size of each table of the pymodbus test device: addresses 0..SIZE-1 exist, SIZE and above do not.
SIZE = 200
#: Writing a value above this to a holding register makes the pymodbus device answer exception 03.
MAX_ALLOWED_VALUE = 50000

FRAMERS = {"tcp": FramerType.SOCKET, "rtu": FramerType.RTU, "ascii": FramerType.ASCII}

# pymodbus logs every exception response it sends as an error; the tests provoke them on purpose.
logging.getLogger("pymodbus").setLevel(logging.CRITICAL)


async def _reject_big_values(function_code, start_address, address, count, registers, set_values):
    """A device rule: holding registers hold at most MAX_ALLOWED_VALUE, else 'illegal data value'."""
    if function_code in (6, 16) and set_values and any(v > MAX_ALLOWED_VALUE for v in set_values):
        return ExcCodes.ILLEGAL_VALUE
    return None


def pymodbus_device(unit: int = 1, *, coils=None, discrete=None, holding=None, inputs=None) -> SimDevice:
    """A pymodbus 3.16 device with four separate tables of SIZE entries each (bit addressing).

    ``coils`` ... ``inputs`` are optional initial value lists (padded with zeros / False).
    """

    def bits(values):
        values = list(values or [])
        return [SimData(0, values=values + [False] * (SIZE - len(values)), datatype=DataType.BITS)]

    def regs(values):
        values = list(values or [])
        return [SimData(0, values=values + [0] * (SIZE - len(values)), datatype=DataType.REGISTERS)]

    return SimDevice(
        id=unit,
        simdata=(bits(coils), bits(discrete), regs(holding), regs(inputs)),
        action=_reject_big_values,
    )


class PymodbusServer:
    """A pymodbus ``ModbusTcpServer`` on its own asyncio loop in a thread: ``with PymodbusServer() as s``.

    ``framer``: ``"tcp"`` (MBAP), ``"rtu"`` or ``"ascii"`` (serial framing carried over TCP, which our
    ``serial_link("socket://...")`` speaks).  ``sslctx``: a server TLS context, for a ``ModbusTlsServer``
    (Modbus/TCP Security).  ``s.port`` is the port it listens on.
    """

    def __init__(self, devices: SimDevice | list[SimDevice] | None = None, framer: str = "tcp",
                 sslctx=None) -> None:
        self.devices = devices if devices is not None else pymodbus_device()
        self.framer = FRAMERS[framer]
        self.sslctx = sslctx
        self.port = 0
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self._thread: threading.Thread | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: ModbusTcpServer | None = None

    def _run(self) -> None:
        async def main() -> None:
            if self.sslctx is not None:
                self._server = ModbusTlsServer(self.devices, address=(HOST, 0), sslctx=self.sslctx)
            else:
                self._server = ModbusTcpServer(self.devices, address=(HOST, 0), framer=self.framer)
            await self._server.serve_forever(background=True)
            self.port = self._server.transport.sockets[0].getsockname()[1]
            self._loop = asyncio.get_running_loop()
            self._ready.set()
            await self._server.serving

        try:
            asyncio.run(main())
        except BaseException as exc:  # noqa: BLE001 - reported to the test thread
            self._error = exc
            self._ready.set()

    def start(self) -> PymodbusServer:
        self._thread = threading.Thread(target=self._run, name="pymodbus server", daemon=True)
        self._thread.start()
        if not self._ready.wait(10) or self._error is not None:
            raise RuntimeError(f"pymodbus server did not start: {self._error!r}")
        return self

    def stop(self) -> None:
        if self._loop is not None and self._server is not None and self._loop.is_running():
            asyncio.run_coroutine_threadsafe(self._server.shutdown(), self._loop).result(10)
        if self._thread is not None:
            self._thread.join(10)
            assert not self._thread.is_alive(), "pymodbus server thread did not stop"

    def __enter__(self) -> PymodbusServer:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.stop()


@contextmanager
def raw_client(port: int, timeout: float = 2.0) -> Iterator[socket.socket]:
    """A plain TCP socket to 127.0.0.1:port (for hostile clients), closed at the end."""
    sock = socket.create_connection((HOST, port), timeout=timeout)
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    try:
        yield sock
    finally:
        sock.close()


def recv_exactly(sock: socket.socket, size: int) -> bytes:
    """Read exactly ``size`` bytes (or fail on EOF / timeout)."""
    data = b""
    while len(data) < size:
        chunk = sock.recv(size - len(data))
        if not chunk:
            raise ConnectionError(f"peer closed after {len(data)} of {size} bytes")
        data += chunk
    return data


def recv_frame(sock: socket.socket) -> bytes:
    """Read one Modbus/TCP frame: the 6 bytes up to the length, then ``length`` more."""
    head = recv_exactly(sock, 6)
    return head + recv_exactly(sock, int.from_bytes(head[4:6], "big"))


def is_closed_by_peer(sock: socket.socket, timeout: float = 2.0) -> bool:
    """True if the peer closes the connection within ``timeout`` s (recv returns b'' or resets)."""
    sock.settimeout(timeout)
    try:
        while True:
            data = sock.recv(4096)
            if not data:
                return True
    except (ConnectionResetError, BrokenPipeError):
        return True
    except TimeoutError:
        return False
