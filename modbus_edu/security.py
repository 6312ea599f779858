"""Modbus/TCP Security: TLS contexts, a test PKI, the role in a certificate, and role authorisation.

Plain Modbus/TCP has no authentication and no encryption: whoever reaches port 502 reads and writes
every register.  The *MODBUS/TCP Security Protocol Specification* puts the same MBAP frames inside
**TLS** (1.2 or newer), on port **802** by convention, with **mutual authentication**: the server shows
a certificate to the client and the client shows one to the server, both signed by an authority the
other trusts.  The client's certificate may carry a **role** (an X.509 extension with the OID
:data:`ROLE_OID`, holding the role's name as an ASN.1 UTF8String); the server maps each role to the
functions and addresses it may use, and answers a request outside them with exception **01, illegal
function**.

This module holds what is needed around the sockets:

* :func:`make_test_pki` makes a certificate authority, a server certificate for ``127.0.0.1`` and
  ``localhost``, a client certificate per role, and the bad certificates that tests and the course
  need (expired, signed by another authority, without a role);
* :func:`server_context` and :func:`client_context` make the :class:`ssl.SSLContext` objects that
  :class:`~modbus_edu.links.tcp.TcpServer` (``tls=``) and :func:`~modbus_edu.links.tcp.tcp_link`
  (``tls=``) take;
* :func:`role_of` reads the role out of a certificate;
* :class:`RoleTable` decides a request PDU for a role (:meth:`RoleTable.decide`, a pure function) and
  counts what it allowed and refused (:meth:`RoleTable.check`, what the server calls)::

      pki = mb.security.make_test_pki("pki")
      roles = mb.security.course_roles()
      with mb.TcpServer(meter, tls=mb.security.server_context(pki), authorization=roles) as server:
          link = mb.tcp_link(*server.address, tls=mb.security.client_context(pki, role="viewer"))
          mb.Master(link).write_single_register(unit=1, address=0, value=5)   # exception 01

``cryptography`` is imported only by the functions that make or read certificates.
"""

from __future__ import annotations

import datetime
import ipaddress
import json
import ssl
import threading
from collections import Counter, deque
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace
from typing import Any, NamedTuple

from .codes import WRITE_FUNCTIONS
from .errors import ConfigError, ModbusError, SecurityError, shown
from .pdu import (
    MAX_FIFO_COUNT,
    ExceptionCode,
    ExceptionResponse,
    ReadFifoQueueRequest,
    ReadFileRecordRequest,
    WriteFileRecordRequest,
    decode_pdu,
)

__all__ = [
    "ROLE_OID",
    "MODBUS_SECURITY_PORT",
    "COURSE_ROLES",
    "CertPair",
    "Pki",
    "Grant",
    "Decision",
    "RoleTable",
    "course_roles",
    "load_roles",
    "make_test_pki",
    "server_context",
    "client_context",
    "role_of",
    "role_extension_value",
    "touched_addresses",
]

#: The X.509 extension that carries a client's role (Modbus/TCP Security, "RoleOID").
ROLE_OID = "1.3.6.1.4.1.50316.802.1"
#: The TCP port of Modbus/TCP Security ("mbap/s"), as 502 is plain Modbus/TCP's.
MODBUS_SECURITY_PORT = 802
#: The roles :func:`make_test_pki` makes client certificates for, and :func:`course_roles` knows.
COURSE_ROLES = ("viewer", "operator", "engineer")

_UTF8STRING = 0x0C  # the ASN.1 tag of a UTF8String


# --------------------------------------------------------------------------------------------------
# the role extension
# --------------------------------------------------------------------------------------------------
def role_extension_value(role: str) -> bytes:
    """The DER bytes of the role extension's value: an ASN.1 UTF8String holding ``role``.

    >>> role_extension_value("viewer").hex(" ")
    '0c 06 76 69 65 77 65 72'
    """
    if not isinstance(role, str) or not role:
        raise ConfigError(f"a role is a non-empty text such as 'viewer', got {shown(role)}")
    text = role.encode("utf-8")
    size = len(text)
    if size < 0x80:
        length = bytes([size])
    elif size <= 0xFFFF:
        length = bytes([0x82]) + size.to_bytes(2, "big")
    else:
        raise ConfigError(f"a role of {size} bytes is far longer than any role name")
    return bytes([_UTF8STRING]) + length + text


def _parse_role_value(data: bytes) -> str:
    """The role text inside the extension's DER value; SecurityError naming the byte that is wrong."""
    if len(data) < 2 or data[0] != _UTF8STRING:
        tag = f"0x{data[0]:02X}" if data else "nothing"
        raise SecurityError(
            f"the role extension ({ROLE_OID}) must hold an ASN.1 UTF8String (tag 0x0C at byte 0), "
            f"found {tag}"
        )
    size, start = data[1], 2
    if size & 0x80:
        count = size & 0x7F
        if count not in (1, 2) or len(data) < 2 + count:
            raise SecurityError(f"the role extension's length at byte 1 (0x{size:02X}) is not a DER length "
                                "of one or two bytes")
        size, start = int.from_bytes(data[2:2 + count], "big"), 2 + count
    if len(data) != start + size:
        raise SecurityError(f"the role extension says {size} bytes of text from byte {start}, "
                            f"but holds {len(data) - start}")
    try:
        return data[start:].decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SecurityError(f"the role extension's text is not UTF-8 (byte {start + exc.start})") from None


def _cryptography() -> SimpleNamespace:
    """The parts of cryptography this module uses: ``x509``, ``ec``, ``hashes``, ``serialization``."""
    # cryptography takes a moment to import: loaded on first use, not by ``import modbus_edu``
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec

    return SimpleNamespace(x509=x509, ec=ec, hashes=hashes, serialization=serialization)


def load_x509() -> Any:
    """``cryptography.x509``, imported on first use (it takes a moment: a server loads it at start)."""
    return _cryptography().x509


def _load_certificate(certificate: Any) -> Any:
    x509 = load_x509()

    if isinstance(certificate, x509.Certificate):
        return certificate
    if isinstance(certificate, (str, Path)):
        try:
            certificate = Path(certificate).read_bytes()
        except OSError as exc:
            raise SecurityError(f"cannot read the certificate {certificate}: {exc.strerror or exc}") from None
    if not isinstance(certificate, (bytes, bytearray)):
        raise ConfigError("a certificate is a cryptography x509.Certificate, DER or PEM bytes, or a "
                          f"path to a PEM file; got {type(certificate).__name__}")
    data = bytes(certificate)
    try:
        if data.lstrip().startswith(b"-----BEGIN"):
            return x509.load_pem_x509_certificate(data)
        return x509.load_der_x509_certificate(data)
    except ValueError as exc:
        raise SecurityError(f"not an X.509 certificate ({exc})") from None


def role_of(certificate: Any) -> str | None:
    """The Modbus role in a certificate (the :data:`ROLE_OID` extension), or None if it has none.

    ``certificate``: what ``ssl.SSLSocket.getpeercert(binary_form=True)`` gives (DER bytes), PEM
    bytes, a path to a PEM file, or a ``cryptography`` certificate.
    """
    x509 = load_x509()

    cert = _load_certificate(certificate)
    try:
        ext = cert.extensions.get_extension_for_oid(x509.ObjectIdentifier(ROLE_OID))
    except x509.ExtensionNotFound:
        return None
    return _parse_role_value(ext.value.value)


# --------------------------------------------------------------------------------------------------
# the test PKI
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CertPair:
    """A certificate and its private key, as PEM files."""

    cert: Path
    key: Path


@dataclass(frozen=True)
class Pki:
    """The files :func:`make_test_pki` wrote.

    ``ca_cert``  the authority both sides trust;  ``server_cert``/``server_key``  the server's pair
    (valid for 127.0.0.1, ::1 and localhost);  ``client_cert``/``client_key``  the default client's
    pair (role ``client_role``);  ``roles[name]``  a client pair per role;  ``expired``  a client pair
    whose validity ended yesterday;  ``foreign``  a client pair signed by another authority
    (``foreign_ca_cert``);  ``no_role``  a valid client pair without the role extension.
    """

    directory: Path
    ca_cert: Path
    server_cert: Path
    server_key: Path
    client_cert: Path
    client_key: Path
    client_role: str
    roles: Mapping[str, CertPair]
    expired: CertPair
    foreign: CertPair
    foreign_ca_cert: Path
    no_role: CertPair

    def pair(self, role: str) -> CertPair:
        """The client pair of ``role``; ConfigError naming the roles there are."""
        try:
            return self.roles[role]
        except (KeyError, TypeError):
            raise ConfigError(
                f"this PKI has no client certificate for the role {shown(role)}; it has "
                f"{', '.join(sorted(self.roles))}"
            ) from None


def _new_key() -> Any:
    ec = _cryptography().ec
    return ec.generate_private_key(ec.SECP256R1())


def _write_pair(directory: Path, name: str, cert: Any, key: Any) -> CertPair:
    serialization = _cryptography().serialization
    cert_path, key_path = directory / f"{name}.crt", directory / f"{name}.key"
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    key_path.write_bytes(key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                           serialization.NoEncryption()))
    key_path.chmod(0o600)
    return CertPair(cert_path, key_path)


def _certificate(subject: str, key: Any, issuer: tuple[str, Any] | None, *, start: datetime.datetime,
                 end: datetime.datetime, kind: str, role: str | None = None) -> Any:
    """One certificate: ``kind`` is "ca", "server" or "client"; ``issuer`` (name, key), None: itself."""
    crypto = _cryptography()
    x509, hashes = crypto.x509, crypto.hashes
    ExtendedKeyUsageOID, NameOID = x509.ExtendedKeyUsageOID, x509.NameOID  # noqa: N806 (cryptography's names)

    name = x509.Name([x509.NameAttribute(NameOID.ORGANIZATION_NAME, "modbus_edu test PKI"),
                      x509.NameAttribute(NameOID.COMMON_NAME, subject)])
    issuer_name, issuer_key = (name, key) if issuer is None else (
        x509.Name([x509.NameAttribute(NameOID.ORGANIZATION_NAME, "modbus_edu test PKI"),
                   x509.NameAttribute(NameOID.COMMON_NAME, issuer[0])]), issuer[1])
    builder = (x509.CertificateBuilder().subject_name(name).issuer_name(issuer_name)
               .public_key(key.public_key()).serial_number(x509.random_serial_number())
               .not_valid_before(start).not_valid_after(end)
               .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
               .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(issuer_key.public_key()),
                              critical=False))
    if kind == "ca":
        builder = builder.add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
        usage = dict(digital_signature=False, key_cert_sign=True, crl_sign=True)
    else:
        builder = builder.add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
        usage = dict(digital_signature=True, key_cert_sign=False, crl_sign=False)
        purpose = ExtendedKeyUsageOID.SERVER_AUTH if kind == "server" else ExtendedKeyUsageOID.CLIENT_AUTH
        builder = builder.add_extension(x509.ExtendedKeyUsage([purpose]), critical=False)
    builder = builder.add_extension(x509.KeyUsage(content_commitment=False, key_encipherment=False,
                                                  data_encipherment=False, key_agreement=False,
                                                  encipher_only=False, decipher_only=False, **usage),
                                    critical=True)
    if kind == "server":
        builder = builder.add_extension(x509.SubjectAlternativeName([
            x509.DNSName("localhost"), x509.IPAddress(ipaddress.ip_address("127.0.0.1")),
            x509.IPAddress(ipaddress.ip_address("::1"))]), critical=False)
    if role is not None:
        builder = builder.add_extension(
            x509.UnrecognizedExtension(x509.ObjectIdentifier(ROLE_OID), role_extension_value(role)),
            critical=False)
    return builder.sign(issuer_key, hashes.SHA256())


def make_test_pki(directory: str | Path, *, roles: Iterable[str] = COURSE_ROLES,
                  client_role: str = "operator", days: int = 365) -> Pki:
    """Make a small public-key infrastructure for tests and the course, as PEM files in ``directory``.

    A certificate authority (``ca.crt``); a server certificate for 127.0.0.1, ::1 and localhost;
    a client certificate for each of ``roles`` (``client-viewer.crt`` ...), the role in the
    :data:`ROLE_OID` extension; and three client certificates that a server must refuse or treat
    apart: one expired yesterday (``client-expired.crt``), one signed by another authority
    (``client-foreign.crt``, with ``foreign-ca.crt``), one without a role (``client-norole.crt``).
    Keys are ECDSA P-256 (quick to make), valid ``days`` days from an hour ago.  For tests and
    teaching only: the private keys lie unencrypted in ``directory``.
    """
    roles = tuple(roles)
    for role in roles:
        role_extension_value(role)
    if client_role not in roles:
        raise ConfigError(f"client_role {shown(client_role)} must be one of the roles {roles}")
    if isinstance(days, bool) or not isinstance(days, int) or not 1 <= days <= 36500:
        raise ConfigError(f"days must be a whole number of days 1..36500, got {shown(days)}")
    folder = Path(directory)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SecurityError(f"cannot make the PKI folder {folder}: {exc.strerror or exc}") from None
    now = datetime.datetime.now(datetime.timezone.utc)
    start, end = now - datetime.timedelta(hours=1), now + datetime.timedelta(days=days)
    ca_key, foreign_key = _new_key(), _new_key()
    ca = ("modbus_edu test CA", ca_key)
    foreign = ("another CA", foreign_key)
    ca_pair = _write_pair(folder, "ca", _certificate(ca[0], ca_key, None, start=start, end=end, kind="ca"),
                          ca_key)
    foreign_ca = _write_pair(folder, "foreign-ca", _certificate(foreign[0], foreign_key, None, start=start,
                                                                end=end, kind="ca"), foreign_key)

    def issue(name: str, subject: str, kind: str, role: str | None, by: tuple[str, Any] = ca,
              begin: datetime.datetime = start, until: datetime.datetime = end) -> CertPair:
        key = _new_key()
        cert = _certificate(subject, key, by, start=begin, end=until, kind=kind, role=role)
        return _write_pair(folder, name, cert, key)

    server = issue("server", "127.0.0.1", "server", None)
    pairs = {role: issue(f"client-{role}", f"{role} client", "client", role) for role in roles}
    expired = issue("client-expired", f"{client_role} client (expired)", "client", client_role,
                    begin=now - datetime.timedelta(days=30), until=now - datetime.timedelta(days=1))
    stranger = issue("client-foreign", f"{client_role} client (another CA)", "client", client_role,
                     by=foreign)
    no_role = issue("client-norole", "client without a role", "client", None)
    default = pairs[client_role]
    return Pki(directory=folder, ca_cert=ca_pair.cert, server_cert=server.cert, server_key=server.key,
               client_cert=default.cert, client_key=default.key, client_role=client_role, roles=pairs,
               expired=expired, foreign=stranger, foreign_ca_cert=foreign_ca.cert, no_role=no_role)


# --------------------------------------------------------------------------------------------------
# TLS contexts
# --------------------------------------------------------------------------------------------------
def _load(context: ssl.SSLContext, cert: Any, key: Any, ca: Any, what: str) -> ssl.SSLContext:
    context.minimum_version = ssl.TLSVersion.TLSv1_2
    try:
        if cert is not None:
            context.load_cert_chain(str(cert), None if key is None else str(key))
        context.load_verify_locations(cafile=str(ca))
    except FileNotFoundError as exc:
        raise SecurityError(f"{what}: no such file {exc.filename}") from None
    except (ssl.SSLError, OSError) as exc:
        raise SecurityError(
            f"{what}: cannot load the certificate {cert}, its key {key} or the authority {ca} "
            f"({getattr(exc, 'reason', None) or exc}); they must be PEM files, the key the certificate's own"
        ) from None
    return context


def _files(pki: Pki | None, cert: Any, key: Any, ca: Any, what: str) -> tuple[Any, Any, Any]:
    if pki is not None and not isinstance(pki, Pki):
        raise ConfigError(f"{what}: expected the Pki that make_test_pki returned, got {type(pki).__name__}")
    if ca is None:
        if pki is None:
            raise ConfigError(f"{what} needs the certificate authority to trust: pass a Pki or ca=PATH")
        ca = pki.ca_cert
    return cert, key, ca


def server_context(pki: Pki | None = None, *, cert: Any = None, key: Any = None, ca: Any = None
                   ) -> ssl.SSLContext:
    """A TLS context for a Modbus/TCP Security server: TLS 1.2 or newer, the server's certificate and
    key, and a **required** client certificate signed by the authority ``ca``.

    From a :class:`Pki` (``server_context(pki)``) or from files (``cert=``, ``key=``, ``ca=``; those
    given override the PKI's), as the command line's ``--tls-cert/--tls-key/--tls-ca`` do.
    """
    cert, key, ca = _files(pki, cert, key, ca, "server_context")
    if cert is None:
        if pki is None:
            raise ConfigError("server_context needs the server's certificate and key: pass a Pki or "
                              "cert=PATH, key=PATH")
        cert, key = pki.server_cert, pki.server_key
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.verify_mode = ssl.CERT_REQUIRED
    return _load(context, cert, key, ca, "server_context")


def client_context(pki: Pki | None = None, role: str | None = None, *, cert: Any = None, key: Any = None,
                   ca: Any = None, certificate: bool = True) -> ssl.SSLContext:
    """A TLS context for a Modbus/TCP Security client: TLS 1.2 or newer, the server's certificate
    checked against the authority ``ca`` and the host name, and the client's own certificate.

    ``role`` picks the PKI's client pair of that role (default: the PKI's ``client_cert``); ``cert=``
    and ``key=`` give another pair (``pki.expired``, ``pki.foreign``, or your own files);
    ``certificate=False`` makes a client that shows no certificate at all (a server must refuse it).
    """
    cert, key, ca = _files(pki, cert, key, ca, "client_context")
    if not certificate:
        if role is not None or cert is not None:
            raise ConfigError("client_context: certificate=False shows no certificate; give no role or cert")
    elif cert is None:
        if pki is None:
            raise ConfigError("client_context needs the client's certificate and key: pass a Pki or "
                              "cert=PATH, key=PATH")
        pair = pki.pair(role) if role is not None else CertPair(pki.client_cert, pki.client_key)
        cert, key = pair.cert, pair.key
    elif role is not None:
        raise ConfigError("client_context: give a role or a cert, not both (the role is in the certificate)")
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)  # checks the host name and the chain
    return _load(context, cert if certificate else None, key, ca, "client_context")


# --------------------------------------------------------------------------------------------------
# role authorisation
# --------------------------------------------------------------------------------------------------
#: The function codes that read and do not change anything.
READ_FUNCTIONS = frozenset({1, 2, 3, 4, 7, 11, 12, 17, 20, 24, 43})
#: Which table each function code's address field points into.
_TABLES = {1: "coils", 5: "coils", 15: "coils", 2: "discrete inputs", 4: "input registers",
           3: "holding registers", 6: "holding registers", 16: "holding registers",
           22: "holding registers", 23: "holding registers", 24: "holding registers",
           20: "file records", 21: "file records"}


def touched_addresses(request: Any) -> list[range]:
    """The addresses a decoded request reads or writes, as ranges (empty for functions without any).

    Most requests name them (an address and a count or values).  Two kinds reach further than their
    fields say: FC 24 reads the count at its pointer address and up to 31 queued registers after it,
    so it may touch the pointer and the 31 addresses that follow (within 0..65535); FC 20 and 21 reach
    the records of each sub-request, so for them the record numbers are the addresses (in any file).

    >>> from modbus_edu.pdu import ReadFifoQueueRequest, ReadHoldingRegistersRequest
    >>> touched_addresses(ReadHoldingRegistersRequest(address=10, count=3))
    [range(10, 13)]
    >>> touched_addresses(ReadFifoQueueRequest(address=99))
    [range(99, 131)]
    """
    if isinstance(request, ReadFifoQueueRequest):
        return [range(request.address, min(request.address + 1 + MAX_FIFO_COUNT, 0x10000))]
    if isinstance(request, ReadFileRecordRequest):
        return [range(record, record + length) for _file, record, length in request.records]
    if isinstance(request, WriteFileRecordRequest):
        return [range(record, record + len(values)) for _file, record, values in request.records]
    if hasattr(request, "read_address"):  # FC 23: a write range and a read range
        return [range(request.write_address, request.write_address + len(request.values)),
                range(request.read_address, request.read_address + request.read_count)]
    address = getattr(request, "address", None)
    if address is None:
        return []
    count = getattr(request, "count", None)
    if count is None:
        values = getattr(request, "values", None)
        count = len(values) if values is not None else 1
    return [range(address, address + count)]


@dataclass(frozen=True)
class Grant:
    """What a role may do: these ``functions`` on these ``addresses`` (a range; default: all 65536).

    The range bounds every address a request touches (:func:`touched_addresses`), in whichever table
    the function reaches; for FC 20 and 21 it bounds the record numbers, in every file.
    """

    functions: frozenset[int]
    addresses: range = range(0, 65536)

    def __post_init__(self) -> None:
        functions = frozenset(self.functions)
        if not functions or any(isinstance(f, bool) or not isinstance(f, int) or not 1 <= f <= 127
                                for f in functions):
            raise ConfigError(f"a Grant's functions are function codes 1..127, got {sorted(self.functions)}")
        if not isinstance(self.addresses, range) or self.addresses.step != 1:
            raise ConfigError(
                f"a Grant's addresses are a range such as range(0, 100), got {shown(self.addresses)}")
        object.__setattr__(self, "functions", functions)


class Decision(NamedTuple):
    """What :meth:`RoleTable.decide` says: ``allowed``, why, and the exception response if refused."""

    allowed: bool
    reason: str
    response: bytes | None  # the PDU to answer with: exception 01 (function | 0x80, 0x01)


def _covers(grant: Grant, span: range) -> bool:
    return span.start in grant.addresses and span.stop - 1 in grant.addresses


def _refuse(function: int, reason: str) -> Decision:
    pdu = ExceptionResponse(function=function, code=ExceptionCode.ILLEGAL_FUNCTION).encode()
    return Decision(False, reason, pdu)


@dataclass
class RoleTable:
    """Roles to rights: ``RoleTable({"viewer": [Grant({3, 4})], ...})``.

    A request is allowed if one grant of the client's role holds its function code and every address
    it touches (:func:`touched_addresses`).  A client whose certificate has no role, or a role not in
    the table, gets the grants of ``default`` (None: nothing).  Refused requests are answered with
    exception 01, illegal function, as Modbus/TCP Security says.

    :meth:`decide` is pure (a PDU and a role in, a :class:`Decision` out); :meth:`check` decides and
    counts (``allowed``, ``refused``, ``refused_by_role``) and keeps the last ``log_size`` refusals in
    ``log``.  A server calls :meth:`check` from its own thread; reading the counters is safe anywhere.
    """

    rules: Mapping[str, Any]
    default: str | None = None
    log_size: int = 100
    allowed: int = 0
    refused: int = 0
    refused_by_role: Counter = field(default_factory=Counter)
    log: deque = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.rules, Mapping):
            raise ConfigError(
                f"a RoleTable's rules map a role name to grants, got {type(self.rules).__name__}")
        table: dict[str, tuple[Grant, ...]] = {}
        for role, grants in self.rules.items():
            if not isinstance(role, str) or not role:
                raise ConfigError(f"a role is a non-empty text, got {shown(role)}")
            grants = (grants,) if isinstance(grants, Grant) else tuple(grants)
            if not all(isinstance(g, Grant) for g in grants):
                raise ConfigError(f"the rights of role {shown(role)} must be Grant objects")
            table[role] = grants
        if self.default is not None and self.default not in table:
            raise ConfigError(f"default role {shown(self.default)} is not in the table ({', '.join(table)})")
        self.rules = table
        self.log = deque(maxlen=max(1, int(self.log_size)))
        self._lock = threading.Lock()

    def decide(self, pdu: bytes, role: str | None) -> Decision:
        """Whether ``role`` may send the request ``pdu`` (function code first). Counts nothing."""
        if not isinstance(pdu, (bytes, bytearray)) or not pdu:
            raise ConfigError("decide() takes the request PDU as bytes, function code first")
        function = pdu[0]
        who = f"role {role!r}" if role is not None else "a client without a role"
        grants = self.rules.get(role) if role is not None else None
        if grants is None:
            if self.default is None:
                return _refuse(function & 0x7F or 1, f"{who} has no rights here (not in the role table)")
            grants = self.rules[self.default]
        mine = [g for g in grants if function in g.functions]
        if not mine:
            return _refuse(function & 0x7F or 1, f"{who} may not use function {function} (0x{function:02X})")
        try:
            spans = touched_addresses(decode_pdu(bytes(pdu), "request"))
        except ModbusError:
            return Decision(True, f"function {function} allowed; the slave judges the malformed request",
                            None)
        for grant in mine:
            if all(_covers(grant, span) for span in spans):
                return Decision(True, f"{who} may use function {function} there", None)
        outside = [span for span in spans if not any(_covers(grant, span) for grant in mine)] or spans
        where = ", ".join(f"{s.start}..{s.stop - 1}" for s in outside)
        table = _TABLES.get(function, "the data model")
        return _refuse(function, f"{who} may use function {function} but not on {table} {where}")

    def describe(self) -> str:
        """The table in one line: each role's function codes and addresses, and what a client with no
        role (or one not in the table) gets."""
        def grant(g: Grant) -> str:
            span = g.addresses
            where = "" if span == range(0, 65536) else f" at {span.start}..{span.stop - 1}"
            return f"FC {_runs(sorted(g.functions))}{where}"

        roles = "; ".join(f"{role} {' and '.join(grant(g) for g in grants)}"
                          for role, grants in self.rules.items())
        other = f"those of {self.default!r}" if self.default is not None else "nothing"
        return f"{roles}; a client without a role in the table: {other}"

    def check(self, pdu: bytes, role: str | None, peer: Any = None) -> Decision:
        """:meth:`decide`, counted; a refusal is logged with ``peer``."""
        decision = self.decide(pdu, role)
        with self._lock:
            if decision.allowed:
                self.allowed += 1
            else:
                self.refused += 1
                self.refused_by_role[role] += 1
                self.log.append(f"{peer}: {decision.reason}" if peer is not None else decision.reason)
        return decision


def _runs(codes: list[int]) -> str:
    """1, 2, 3, 4, 7 -> '1-4, 7'."""
    parts: list[str] = []
    for code in codes:
        if parts and code == parts[-1][1] + 1:
            parts[-1] = (parts[-1][0], code)
        else:
            parts.append((code, code))
    return ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in parts)


def load_roles(path: str | Path) -> RoleTable:
    """A :class:`RoleTable` from a JSON file (what ``modbus-edu serve --roles FILE`` reads)::

        {"roles": {"viewer":   [{"functions": [1, 2, 3, 4]}],
                   "operator": [{"functions": [1, 2, 3, 4]},
                                {"functions": [5, 6, 15, 16], "addresses": [0, 99]}]},
         "default": null}

    Each grant is function codes and, optionally, the first and last address it covers (default: all);
    ``default`` names the role whose grants a client without a known role gets (null: nothing).
    """
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise ConfigError(f"cannot read the role table {str(path)!r}: {exc.strerror or exc}") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise ConfigError(f"the role table {str(path)!r} is not JSON: {exc}") from None
    if (not isinstance(data, dict) or not isinstance(data.get("roles"), dict)
            or set(data) - {"roles", "default"}):
        raise ConfigError(f"the role table {str(path)!r} must be an object with \"roles\" (role -> list of "
                          f"grants) and optionally \"default\"")
    rules = {}
    for role, grants in data["roles"].items():
        if not isinstance(grants, list):
            raise ConfigError(f"role {shown(role)} in {str(path)!r}: a list of grants such as "
                              f"[{{\"functions\": [3]}}], got {shown(grants)}")
        rules[role] = [_grant(role, g, path) for g in grants]
    return RoleTable(rules, default=data.get("default"))


def _grant(role: str, entry: Any, path: Any) -> Grant:
    where = f"role {role!r} in {str(path)!r}"
    if not isinstance(entry, dict) or "functions" not in entry or set(entry) - {"functions", "addresses"}:
        raise ConfigError(f"{where}: a grant is {{\"functions\": [...], \"addresses\": [first, last]}}, "
                          f"got {shown(entry)}")
    functions, span = entry["functions"], entry.get("addresses", [0, 65535])
    if not isinstance(functions, list):
        raise ConfigError(f"{where}: \"functions\" is a list of function codes, got {shown(functions)}")
    if (not isinstance(span, list) or len(span) != 2 or not all(type(a) is int for a in span)
            or not 0 <= span[0] <= span[1] <= 65535):
        raise ConfigError(f"{where}: \"addresses\" is [first, last] within 0..65535, got {shown(span)}")
    return Grant(frozenset(functions), range(span[0], span[1] + 1))


def course_roles() -> RoleTable:
    """The course's role table: a ``viewer`` reads; an ``operator`` reads and writes addresses 0..99;
    an ``engineer`` uses every function everywhere.  A client without a role gets nothing."""
    return RoleTable({
        "viewer": [Grant(READ_FUNCTIONS)],
        "operator": [Grant(READ_FUNCTIONS), Grant(WRITE_FUNCTIONS, range(0, 100))],
        "engineer": [Grant(frozenset(range(1, 128)))],
    })
