"""TLS on the course's TCP sockets (Modbus/TCP Security): the server's non-blocking handshake, the
client's handshake within a deadline, and what a TLS failure means in words a learner can act on.

:class:`~modbus_edu.links.tcp.TcpServer` serves many clients from one thread, so it cannot wait for a
handshake: :class:`ServerHandshake` takes one step each time the socket is ready and says whether it
needs to read or to write next (OpenSSL's "want read" / "want write"), until the handshake is done or
has failed.  The client's certificate is checked during the handshake; afterwards the server reads the
client's role out of it (:func:`~modbus_edu.security.role_of`).

:func:`client_handshake` is the client's side: :func:`~modbus_edu.links.tcp.tcp_link` wraps its socket
after connecting and finishes the handshake before the connect timeout runs out.

:func:`tls_failure` turns an ``ssl.SSLError`` into a sentence: the certificate expired, is signed by an
authority the other side does not trust, is missing, names another host...
"""

from __future__ import annotations

import socket
import time
from typing import Any

from ..errors import ConfigError, LinkError

try:
    import ssl
except ImportError:  # pragma: no cover - Pyodide ships ssl apart; without it there is no TLS (nor sockets)
    ssl = None  # type: ignore[assignment]

__all__ = ["SSLError", "WOULD_BLOCK", "ServerHandshake", "TlsRefused", "check_context", "client_handshake",
           "pending", "tls_failure"]

#: ``ssl.SSLError`` (a stand-in that nothing raises where Python has no ssl module).
SSLError: type[OSError] = ssl.SSLError if ssl is not None else type("SSLError", (OSError,), {})
#: What a non-blocking socket raises when it has to wait, TLS or not.
WOULD_BLOCK = (BlockingIOError, InterruptedError) + (
    (ssl.SSLWantReadError, ssl.SSLWantWriteError) if ssl is not None else ())

# OpenSSL's certificate verification codes (X509_V_ERR_*) that a learner meets, and what they mean.
_VERIFY = {
    9: "is not valid yet (its start date is in the future: check the computer's clock)",
    10: "has expired",
    18: "is self-signed and not trusted",
    19: "is signed by an authority that is not trusted here (a self-signed CA not in the trust list)",
    20: "is signed by an authority that is not trusted here (another CA: load that CA with --tls-ca)",
    21: "is signed by an authority that is not trusted here",
    62: "is for another host name or IP address (its subjectAltName does not list this one)",
}
# The alerts one side sends when it refuses the other's certificate (OpenSSL's reason names).
_ALERTS = {
    "TLSV13_ALERT_CERTIFICATE_REQUIRED": "the server requires a client certificate and we showed none",
    "PEER_DID_NOT_RETURN_A_CERTIFICATE": "the client showed no certificate; Modbus/TCP Security requires one",
    "SSLV3_ALERT_CERTIFICATE_EXPIRED": "{other} refused our certificate: it has expired",
    "TLSV1_ALERT_UNKNOWN_CA": "{other} refused our certificate: it does not trust the authority that "
                              "signed it",
    "SSLV3_ALERT_BAD_CERTIFICATE": "{other} refused our certificate",
    "SSLV3_ALERT_CERTIFICATE_UNKNOWN": "{other} refused our certificate",
    "TLSV1_ALERT_PROTOCOL_VERSION": "the two sides share no TLS version (Modbus/TCP Security needs 1.2+)",
    "UNSUPPORTED_PROTOCOL": "the two sides share no TLS version (Modbus/TCP Security needs 1.2+)",
    "WRONG_VERSION_NUMBER": "{other} does not speak TLS (plain Modbus/TCP on a TLS port, or the "
                            "reverse?)",
    "HTTP_REQUEST": "{other} does not speak TLS",
    "UNEXPECTED_EOF_WHILE_READING": "{other} closed the connection in the middle of the handshake",
}


def tls_failure(exc: BaseException, whose: str = "the other side's", other: str = "the other side") -> str:
    """What an ``ssl.SSLError`` (or another OSError during TLS) means, in one sentence.

    ``whose``: whose certificate a verification failure is about ("the server's" on the client,
    "the client's" on the server); ``other``: who sent an alert ("the server", "the client").
    """
    if isinstance(exc, ssl.SSLCertVerificationError):
        meaning = _VERIFY.get(getattr(exc, "verify_code", None))
        detail = getattr(exc, "verify_message", None) or exc.reason or exc
        if meaning:
            return f"{whose} certificate {meaning} ({detail})"
        return f"{whose} certificate was not accepted ({detail})"
    if isinstance(exc, ssl.SSLError):
        reason = exc.reason or ""
        if reason in _ALERTS:
            return f"{_ALERTS[reason].format(other=other)} ({reason.lower().replace('_', ' ')})"
        return f"TLS failed: {reason.lower().replace('_', ' ') or exc}"
    if isinstance(exc, OSError):
        return f"the connection failed during TLS: {exc.strerror or exc}"
    return f"TLS failed: {exc}"


class TlsRefused(Exception):
    """A server-side handshake failed; ``str()`` says why (see :func:`tls_failure`)."""


def check_context(context: Any, side: str) -> ssl.SSLContext | None:
    """``context`` if it is an ``ssl.SSLContext`` fit for ``side`` ("server" or "client"), or None."""
    if context is None:
        return None
    if ssl is None:  # pragma: no cover - Pyodide without its ssl package
        raise ConfigError("TLS is not available in this Python (it has no ssl module)")
    if not isinstance(context, ssl.SSLContext):
        raise ConfigError(f"tls= takes an ssl.SSLContext (modbus_edu.security.{side}_context(...)), "
                          f"got {type(context).__name__}")
    if side == "server" and context.verify_mode != ssl.CERT_REQUIRED:
        raise ConfigError("Modbus/TCP Security requires mutual authentication: the server's context must "
                          "require a client certificate (verify_mode CERT_REQUIRED, as "
                          "modbus_edu.security.server_context makes it)")
    if context.minimum_version not in (ssl.TLSVersion.MINIMUM_SUPPORTED, ssl.TLSVersion.TLSv1_2,
                                       ssl.TLSVersion.TLSv1_3, ssl.TLSVersion.MAXIMUM_SUPPORTED):
        raise ConfigError(f"Modbus/TCP Security needs TLS 1.2 or newer; the context allows "
                          f"{context.minimum_version.name}")
    if context.minimum_version == ssl.TLSVersion.MINIMUM_SUPPORTED:
        context.minimum_version = ssl.TLSVersion.TLSv1_2
    return context


def pending(sock: socket.socket) -> int:
    """Bytes already decrypted and waiting inside a TLS socket (a selector does not see them)."""
    return sock.pending() if ssl is not None and isinstance(sock, ssl.SSLSocket) else 0


class ServerHandshake:
    """The server's side of one TLS handshake on a non-blocking socket, one step at a time.

    ``sock`` is the accepted (non-blocking) socket; :attr:`sock` the TLS socket that replaces it.
    :meth:`step` returns ``"read"`` or ``"write"`` (what to wait for before the next step) or ``"done"``;
    it raises :class:`TlsRefused` when the handshake fails.  ``deadline`` (a ``time.monotonic()``
    value) is when the server gives up on a client that does not finish.
    """

    __slots__ = ("sock", "deadline")

    def __init__(self, context: ssl.SSLContext, sock: socket.socket, deadline: float) -> None:
        self.sock = context.wrap_socket(sock, server_side=True, do_handshake_on_connect=False)
        self.deadline = deadline

    def step(self) -> str:
        try:
            self.sock.do_handshake()
        except ssl.SSLWantReadError:
            return "read"
        except ssl.SSLWantWriteError:
            return "write"
        except (BlockingIOError, InterruptedError):  # pragma: no cover - OpenSSL reports these as wants
            return "read"
        except (ssl.SSLError, OSError) as exc:
            raise TlsRefused(tls_failure(exc, "the client's", "the client")) from exc
        return "done"

    def peer_certificate(self) -> bytes | None:
        """The client's certificate (DER) once the handshake is done."""
        return self.sock.getpeercert(binary_form=True)


def client_handshake(context: ssl.SSLContext, sock: socket.socket, host: str, timeout: float
                     ) -> ssl.SSLSocket:
    """Wrap a connected socket in TLS and finish the handshake within ``timeout`` seconds.

    The server's certificate must be signed by an authority the context trusts and name ``host``.
    A failure closes the socket and raises :class:`~modbus_edu.errors.LinkError` saying why.
    """
    where = f"{host}:{sock.getpeername()[1]}"
    end = time.monotonic() + timeout
    try:
        tls = context.wrap_socket(sock, server_hostname=host, do_handshake_on_connect=False)
    except (ssl.SSLError, ValueError) as exc:
        sock.close()
        raise LinkError(f"cannot start TLS to {where}: {exc}") from None
    try:
        tls.settimeout(max(0.001, end - time.monotonic()))
        tls.do_handshake()
    except TimeoutError:
        tls.close()
        raise LinkError(f"TLS handshake with {where} did not finish within {timeout:g} s - is it a "
                        "Modbus/TCP Security server (port 802 by convention)?") from None
    except (ssl.SSLError, OSError) as exc:
        tls.close()
        why = tls_failure(exc, "the server's", "the server")
        raise LinkError(f"TLS handshake with {where} failed: {why}") from None
    return tls
