"""The :class:`Link`: what a master needs from a wire, whatever the wire is.

A link carries whole frames between a master and the slaves behind it.  The master hands it the bytes
of one request and then waits for the bytes of one response; it does not care whether they travel
through a virtual RS-485 bus inside this Python process, a TCP socket or a USB serial adapter.

Every link has:

``mode``
    ``"rtu"``, ``"ascii"`` or ``"tcp"``: how the frames on it are built.
``clock``
    the clock its timeouts run on: a :class:`~modbus_edu.clock.VirtualClock` for the loopback links
    (time jumps, nothing sleeps for real), a :class:`~modbus_edu.clock.RealClock` for real I/O.
``send(frame)``
    put one complete frame on the wire (the bytes exactly as built, checksum included).
``receive(timeout)``
    wait at most ``timeout`` seconds, on ``clock``, for the next complete frame and return its raw bytes,
    as cut by the link's splitter (a serial link: by the silence after the frame, or by its expected
    length; TCP: by the MBAP length).  ``None`` when the time passes first.  Frames are returned
    unchecked: checking the CRC, the unit, the transaction id is the master's job, so that it can count
    what went wrong.  ``receive(0)`` returns a frame that has already arrived, or ``None`` at once.
``flush()``
    return once everything sent has left the link (and, on a serial line, once the silence that ends
    the frame has passed).  The master calls it after a broadcast, which nobody answers.
``close()``
    release the port or the socket; a closed link raises :class:`~modbus_edu.errors.LinkError`.
    A link is a context manager: ``with mb.tcp_link(host, port) as link: ...`` closes it at the end.
``description``
    one line for people: ``"virtual RS-485, 9600 baud 8N1, RTU, 2 slaves"``.

Writing a new link means subclassing :class:`Link` and implementing ``send`` and ``receive`` (and
``close`` and ``flush`` when there is something to do).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from types import TracebackType

from ..clock import Clock
from ..errors import LinkError

__all__ = ["Link", "READ_CHUNK"]

READ_CHUNK = 4096
"""The most bytes a link reads and cuts into frames before it looks at its deadline again.

Cutting costs time in proportion to the bytes (a run of junk is tried byte by byte), so a peer that
never stops sending could otherwise hold a read past its deadline for as long as one large read takes to
cut: 64 KiB of junk is tens of milliseconds, and many times that on a busy machine."""


class Link(ABC):
    """A wire between a master and its slave(s): ``send`` one frame, ``receive`` one frame.

    Subclasses set :attr:`mode` and :attr:`clock` and implement :meth:`send` and :meth:`receive`.
    """

    mode: str = "rtu"
    """``"rtu"``, ``"ascii"`` or ``"tcp"``: the framing of everything on this link."""

    clock: Clock
    """The clock timeouts are measured on (``link.clock.now`` is the link's time in seconds)."""

    closed: bool = False
    """True once :meth:`close` has been called."""

    @abstractmethod
    def send(self, frame: bytes) -> None:
        """Transmit one complete frame (raw bytes, checksum included)."""

    @abstractmethod
    def receive(self, timeout: float) -> bytes | None:
        """The next complete raw frame, or ``None`` if none is complete within ``timeout`` seconds."""

    def flush(self) -> None:  # noqa: B027 - optional hook, nothing to do by default
        """Wait until everything sent has left the link.  Nothing to do on most links."""

    def close(self) -> None:
        """Release the link's resources.  Closing twice is harmless."""
        self.closed = True

    def _check_open(self) -> None:
        """Raise :class:`LinkError` if the link was closed (for subclasses' ``send``/``receive``)."""
        if self.closed:
            raise LinkError(f"{self.description}: the link is closed; open a new one")

    @property
    def description(self) -> str:
        """A one-line description of the link for people and logs."""
        return f"{type(self).__name__} ({self.mode.upper()})"

    def __enter__(self) -> Link:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self.description}{' (closed)' if self.closed else ''}>"
