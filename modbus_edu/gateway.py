"""A Modbus/TCP-to-serial gateway: a role built from the two others.

In front, a :class:`~modbus_edu.links.tcp.TcpServer` accepts Modbus/TCP clients; behind, a
:class:`~modbus_edu.master.Master` polls the slaves on a serial ``link`` (a ``loopback_serial`` bus or a
real ``serial_link``). Each request's unit id chooses the serial slave; the PDU is forwarded unchanged
and the response goes back with the request's **transaction id** and unit id.

What the client sees when the serial side fails (*Modbus Application Protocol* V1.1b3, section 7):

* **0x0B gateway target device failed to respond** - the slave stayed silent (or only garbled
  answers came back) for the gateway's ``timeout`` on each of its ``retries + 1`` attempts;
* **0x0A gateway path unavailable** - no path to that unit: unit 0 (a serial broadcast, which nobody
  answers while the TCP client waits for an answer), units 248-255 (reserved on a serial line), or the
  serial port itself failing.

The serial bus carries one transaction at a time, so requests from several TCP clients are served one
after the other (the server's lock); a client therefore waits for the others' transactions too - the
stacked timeouts a gateway's users meet. Time one transaction yourself: request characters + 3.5
characters of silence + the slave's processing + response characters + 3.5 characters, at the bus's
character time (:mod:`modbus_edu.links.wire`).

**When the timeout starts.** The serial-line specification (*Modbus over Serial Line* V1.02, section
2.4.1) starts a master's response time-out once the request has been sent, that is when its last byte
has left the wire. This gateway's serial side is a :class:`~modbus_edu.master.Master`, which starts the
clock when it starts sending the request: the request's own characters are inside ``timeout``, so a
silent unit costs ``timeout`` of bus time in all (200 ms for ``timeout=0.2``, of which the 8 characters
of an FC 3 request take 8.33 ms at 9600 baud), not the request plus ``timeout``.
"""

from __future__ import annotations

import threading
from typing import Any

from .errors import AddressRangeError, LinkError, ModbusError, UnknownFunctionError
from .framing import TcpFrame
from .links.base import Link
from .links.routing import exception_reply
from .links.tcp import TcpServer
from .master import Master
from .pdu import ExceptionResponse

__all__ = ["GATEWAY_PATH_UNAVAILABLE", "GATEWAY_TARGET_FAILED", "TcpGateway"]

#: Exception code 0x0A: the gateway has no path to the target.
GATEWAY_PATH_UNAVAILABLE = 0x0A
#: Exception code 0x0B: the target device behind the gateway failed to respond.
GATEWAY_TARGET_FAILED = 0x0B


class _Forwarder:
    """What the TCP server sees as its one slave for every unit: forwards requests to the serial bus."""

    unit = None  # answers any unit (see route_unit)

    def __init__(self, master: Master) -> None:
        self.master = master
        self.clock = master.link.clock
        self.lock = threading.Lock()
        self.forwarded = 0
        self.no_response = 0
        self.path_unavailable = 0

    def handle(self, frame: bytes, mode: str = "tcp") -> bytes | None:
        unit = frame[6]
        if unit == 0 or unit > 247:
            self.path_unavailable += 1
            return exception_reply(frame, GATEWAY_PATH_UNAVAILABLE)
        try:
            request = TcpFrame.decode(frame, role="request")
        except UnknownFunctionError:
            return exception_reply(frame, 0x01)
        except AddressRangeError:
            return exception_reply(frame, 0x02)
        except ModbusError:
            return exception_reply(frame, 0x03)
        with self.lock:  # one transaction at a time on the bus
            self.forwarded += 1
            try:
                response = self.master.execute(unit, request.pdu, check=False)
            except LinkError:
                self.path_unavailable += 1
                return exception_reply(frame, GATEWAY_PATH_UNAVAILABLE)
            except ModbusError:  # timeout, CRC errors, mismatches on every attempt
                self.no_response += 1
                return exception_reply(frame, GATEWAY_TARGET_FAILED)
        if response is None:  # pragma: no cover - unit 0 is refused above
            return None
        if (
            not isinstance(response, ExceptionResponse)
            and response.function_code != request.pdu.function_code
        ):
            return exception_reply(frame, GATEWAY_TARGET_FAILED)
        return TcpFrame(transaction_id=request.transaction_id, unit=unit, pdu=response).encode()


class TcpGateway:
    """Serve Modbus/TCP on ``host:port`` and forward each request to the slaves behind ``link``.

    ``timeout`` is how long the gateway waits for a serial slave (seconds on the link's clock, from the
    moment it starts sending the request: see the module's documentation), and
    ``retries`` how often it asks again before answering 0x0B. A context manager with ``.address``::

        bus = mb.loopback_serial([meter, arduino], baudrate=9600)
        with mb.TcpGateway(bus, timeout=0.1) as gw:
            with mb.tcp_link(*gw.address) as tcp:
                mb.Master(tcp).read_holding_registers(unit=2, address=0, count=2)
    """

    def __init__(
        self,
        link: Link,
        host: str = "127.0.0.1",
        port: int = 0,
        *,
        timeout: float = 0.5,
        retries: int = 0,
        **server_options: Any,
    ) -> None:
        self.link = link
        self.master = Master(link, timeout=timeout, retries=retries)
        self._forwarder = _Forwarder(self.master)
        self.server = TcpServer(self._forwarder, host=host, port=port, **server_options)

    @property
    def address(self) -> tuple[str, int] | None:
        """The (host, port) the gateway listens on (after :meth:`start`)."""
        return self.server.address

    @property
    def counters(self) -> dict[str, int]:
        """Requests forwarded, answered 0x0B (no response) and 0x0A (path unavailable)."""
        f = self._forwarder
        return {
            "forwarded": f.forwarded,
            "no_response": f.no_response,
            "path_unavailable": f.path_unavailable,
        }

    def start(self) -> TcpGateway:
        self.server.start()
        return self

    def close(self) -> None:
        self.server.close()

    def __enter__(self) -> TcpGateway:
        return self.start()

    def __exit__(self, *exc_info: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<TcpGateway {self.address} -> {self.link.description}>"
