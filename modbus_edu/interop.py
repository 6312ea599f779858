"""Running pymodbus beside the course: a real pymodbus server in a background thread.

pymodbus's servers are asyncio coroutines; a notebook or a test that wants one as a *peer* (the other
side of a real socket) needs it in a thread of its own, started and stopped cleanly.  That is all this
module does::

    from pymodbus.simulator import DataType, SimData, SimDevice
    from modbus_edu.interop import pymodbus_server

    device = SimDevice(id=1, simdata=[SimData(0, values=[100, 200], datatype=DataType.REGISTERS)])
    with pymodbus_server(device) as (host, port):
        with mb.tcp_link(host, port) as link:
            print(mb.Master(link).read_holding_registers(unit=1, address=0, count=2))

The server listens on 127.0.0.1 and a free port unless told otherwise; every wait has a deadline.
"""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from pymodbus.framer import FramerType
from pymodbus.server import ModbusTcpServer

from .errors import LinkError, shown
from .platform import require_sockets


@contextmanager
def pymodbus_server(device: Any, framer: str = "socket", host: str = "127.0.0.1", port: int = 0,
                    timeout: float = 10.0) -> Iterator[tuple[str, int]]:
    """Serve ``device`` (a pymodbus ``SimDevice`` or a list of them) with pymodbus's ``ModbusTcpServer``.

    ``framer`` is pymodbus's name of the framing on the socket: ``"socket"`` (Modbus/TCP, the MBAP
    header) or ``"rtu"`` / ``"ascii"`` (serial frames over TCP, as a serial device server sends them).
    Yields the ``(host, port)`` the server listens on; on leaving the block the server shuts down.
    Raises :class:`~modbus_edu.errors.LinkError` if it does not start or stop within ``timeout`` seconds.
    """
    require_sockets("pymodbus's server (pymodbus_server)")
    try:
        framer_type = FramerType(framer)
    except ValueError:
        names = ", ".join(repr(item.value) for item in FramerType)
        raise LinkError(f"framer {shown(framer)} is not one of pymodbus's framers ({names})") from None
    ready = threading.Event()
    state: dict[str, Any] = {}

    async def serve() -> None:
        try:
            server = ModbusTcpServer(device, address=(host, port), framer=framer_type)
            await server.serve_forever(background=True)
            state.update(server=server, loop=asyncio.get_running_loop(),
                         address=server.transport.sockets[0].getsockname()[:2])
        except Exception as exc:  # reported to the caller below, with its cause
            state["error"] = exc
            return
        finally:
            ready.set()
        await server.serving

    thread = threading.Thread(target=asyncio.run, args=(serve(),), name="pymodbus server", daemon=True)
    thread.start()
    if not ready.wait(timeout) or "error" in state:
        raise LinkError(f"the pymodbus server did not start on {host}:{port}: "
                        f"{state.get('error', f'no answer within {timeout:g} s')}")
    try:
        yield state["address"]
    finally:
        stop = asyncio.run_coroutine_threadsafe(state["server"].shutdown(), state["loop"])
        try:
            stop.result(timeout)
        except Exception as exc:
            raise LinkError(f"the pymodbus server did not stop within {timeout:g} s: {exc}") from exc
        thread.join(timeout)
