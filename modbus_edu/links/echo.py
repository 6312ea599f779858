"""Local echo: what to do when a serial adapter hands the master its own request back.

Many USB-RS485 adapters, and every two-wire bus where the transmitter's receiver stays enabled, return
each byte the master sends: the master reads its request first, then the answer.  The fix is usually a
switch or jumper on the adapter ("echo off"); where there is none, the script must read the echo back
and check it before the answer.  :func:`strip_echo` does that on the bytes read from a port: the echo
must be the request exactly (a damaged echo means the line itself is bad), and what follows it is the
answer.
"""

from __future__ import annotations

from ..errors import FrameError

__all__ = ["EchoError", "strip_echo"]


class EchoError(FrameError):
    """The bytes read back do not start with the request that was sent."""


def strip_echo(sent: bytes, received: bytes) -> bytes:
    """The answer in ``received``, once the echo of ``sent`` at its start is taken off.

    >>> request = bytes.fromhex("01 04 00 00 00 02 71 CB")
    >>> strip_echo(request, request + bytes.fromhex("01 04 04 99 9A 43 65 04 2C")).hex(" ")
    '01 04 04 99 9a 43 65 04 2c'

    Raises :class:`EchoError` when ``received`` is shorter than the request or differs from it: the
    echo is missing (the adapter does not echo) or damaged (the line garbles what it carries).
    """
    sent, received = bytes(sent), bytes(received)
    if not sent:
        raise EchoError("nothing was sent, so there is no echo to take off")
    n = len(sent)
    if len(received) < n:
        raise EchoError(f"only {len(received)} bytes came back, fewer than the {n} of the request's echo")
    for index in range(n):
        if received[index] != sent[index]:
            raise EchoError(f"byte {index} of the echo is 0x{received[index]:02X}, the request sent "
                            f"0x{sent[index]:02X}: the echo is missing or damaged")
    return received[n:]
