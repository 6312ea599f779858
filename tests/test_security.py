"""Modbus/TCP Security: the test PKI, the role extension, role authorisation, and TLS on real sockets
(127.0.0.1 only) between this library and pymodbus 3.16, both ways.

What must hold: a client without a certificate, with another authority's or with an expired one gets
nothing and the server's counters and ``tls_log`` say why; a role outside its rights gets exception 01;
the server's defences (handshake deadline, slow and idle clients, connection limit) hold under TLS.
"""

from __future__ import annotations

import datetime
import os
import select
import signal
import socket
import ssl
import subprocess
import sys
import time
import warnings

import pytest
from conftest_io import HOST, PymodbusServer, is_closed_by_peer, pymodbus_device, raw_client, recv_frame
from cryptography import x509
from pymodbus.client import ModbusTlsClient

import modbus_edu as mb
from modbus_edu import security
from modbus_edu.errors import ConfigError, LinkError, ModbusExceptionError, SecurityError
from modbus_edu.links.tls import client_handshake
from modbus_edu.security import (
    Grant,
    RoleTable,
    course_roles,
    role_extension_value,
    role_of,
    touched_addresses,
)


@pytest.fixture(scope="module")
def pki(tmp_path_factory):
    return security.make_test_pki(tmp_path_factory.mktemp("pki"))


def _slave() -> mb.Slave:
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    slave.bank.holding_registers.write(0, [11, 22, 33, 44])
    return slave


@pytest.fixture
def secure(pki):
    """A TLS server with the course's role table; yields (server, slave, roles)."""
    slave, roles = _slave(), course_roles()
    with mb.TcpServer(slave, tls=security.server_context(pki), authorization=roles,
                      handshake_timeout=1.0) as server:
        yield server, slave, roles


def _master(server, pki, **context) -> mb.Master:
    link = mb.tcp_link(*server.address, tls=security.client_context(pki, **context), timeout=3)
    return mb.Master(link, timeout=2)


def _wait_for(condition, seconds: float = 3.0) -> bool:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.01)
    return condition()


# --- the role extension and the PKI -------------------------------------------------------------------
def test_role_extension_is_a_der_utf8string():
    assert role_extension_value("viewer") == bytes.fromhex("0c 06") + b"viewer"
    long = "r" * 200
    assert role_extension_value(long)[:4] == bytes.fromhex("0c 82 00 c8")
    with pytest.raises(ConfigError):
        role_extension_value("")


@pytest.mark.parametrize("value, where", [
    (bytes.fromhex("13 06") + b"viewer", "tag 0x0C"),           # a PrintableString, not a UTF8String
    (bytes.fromhex("0c 09") + b"viewer", "holds 6"),            # the length says more than there is
    (bytes.fromhex("0c 02 ff fe"), "not UTF-8"),
    (b"", "found nothing"),
])
def test_a_broken_role_extension_is_named(pki, value, where):
    from cryptography.hazmat.primitives import hashes, serialization

    key = serialization.load_pem_private_key(pki.no_role.key.read_bytes(), None)
    cert = x509.load_pem_x509_certificate(pki.no_role.cert.read_bytes())
    builder = (x509.CertificateBuilder().subject_name(cert.subject).issuer_name(cert.subject)
               .public_key(key.public_key()).serial_number(1)
               .not_valid_before(cert.not_valid_before_utc).not_valid_after(cert.not_valid_after_utc)
               .add_extension(x509.UnrecognizedExtension(x509.ObjectIdentifier(security.ROLE_OID), value),
                              critical=False))
    with pytest.raises(SecurityError, match=where):
        role_of(builder.sign(key, hashes.SHA256()))


def test_make_test_pki_writes_a_ca_a_server_and_a_client_per_role(pki):
    ca = x509.load_pem_x509_certificate(pki.ca_cert.read_bytes())
    server = x509.load_pem_x509_certificate(pki.server_cert.read_bytes())
    server.verify_directly_issued_by(ca)
    names = server.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert "localhost" in names.get_values_for_type(x509.DNSName)
    assert "127.0.0.1" in [str(ip) for ip in names.get_values_for_type(x509.IPAddress)]
    assert set(pki.roles) == {"viewer", "operator", "engineer"}
    for role, pair in pki.roles.items():
        cert = x509.load_pem_x509_certificate(pair.cert.read_bytes())
        cert.verify_directly_issued_by(ca)
        ext = cert.extensions.get_extension_for_oid(x509.ObjectIdentifier("1.3.6.1.4.1.50316.802.1"))
        assert not ext.critical and ext.value.value == role_extension_value(role)
        assert role_of(pair.cert) == role == role_of(cert.public_bytes(serialization_der()))
    assert role_of(pki.client_cert) == pki.client_role == "operator"
    assert role_of(pki.no_role.cert) is None
    expired = x509.load_pem_x509_certificate(pki.expired.cert.read_bytes())
    assert expired.not_valid_after_utc < datetime.datetime.now(datetime.timezone.utc)
    foreign = x509.load_pem_x509_certificate(pki.foreign.cert.read_bytes())
    with pytest.raises((ValueError, TypeError)):
        foreign.verify_directly_issued_by(ca)
    with pytest.raises(ConfigError, match="viewer"):
        pki.pair("admin")


def serialization_der():
    from cryptography.hazmat.primitives.serialization import Encoding

    return Encoding.DER


def test_contexts_require_tls_1_2_and_a_client_certificate(pki):
    server = security.server_context(pki)
    assert server.verify_mode == ssl.CERT_REQUIRED
    assert server.minimum_version == ssl.TLSVersion.TLSv1_2
    client = security.client_context(pki, role="viewer")
    assert client.check_hostname and client.verify_mode == ssl.CERT_REQUIRED
    assert client.minimum_version == ssl.TLSVersion.TLSv1_2
    lax = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    with pytest.raises(ConfigError, match="mutual authentication"):
        mb.TcpServer(_slave(), tls=lax)
    old = security.server_context(pki)
    with warnings.catch_warnings():  # Python itself frowns on TLS 1.1
        warnings.simplefilter("ignore", DeprecationWarning)
        old.minimum_version = ssl.TLSVersion.TLSv1_1
    with pytest.raises(ConfigError, match="1.2"):
        mb.TcpServer(_slave(), tls=old)
    with pytest.raises(ConfigError, match="SSLContext"):
        mb.tcp_link(HOST, 802, tls="yes")
    with pytest.raises(SecurityError, match="no such file"):
        security.server_context(pki, cert=pki.directory / "missing.crt", key=pki.server_key)
    with pytest.raises(SecurityError, match="cannot load"):
        security.server_context(pki, cert=pki.ca_cert, key=pki.server_key)  # the key is not the CA's


# --- role authorisation, without sockets --------------------------------------------------------------
def _pdu(request) -> bytes:
    return request.encode()


def test_role_table_decides_by_function_and_address():
    roles = course_roles()
    read = _pdu(mb.ReadHoldingRegistersRequest(address=0, count=10))
    write = _pdu(mb.WriteSingleRegisterRequest(address=5, value=1))
    far_write = _pdu(mb.WriteMultipleRegistersRequest(address=98, values=[1, 2, 3]))  # 98..100
    assert roles.decide(read, "viewer").allowed
    refused = roles.decide(write, "viewer")
    assert not refused.allowed and refused.response == bytes.fromhex("86 01")
    assert roles.decide(write, "operator").allowed
    far = roles.decide(far_write, "operator")
    assert far.response == bytes.fromhex("90 01") and "98..100" in far.reason
    assert roles.decide(far_write, "engineer").allowed
    assert roles.decide(read, None).response == bytes.fromhex("83 01")       # no role: nothing
    assert roles.decide(read, "admin").response == bytes.fromhex("83 01")    # unknown role: nothing
    both = mb.ReadWriteMultipleRegistersRequest(read_address=0, read_count=2, write_address=150, values=[1])
    assert not roles.decide(_pdu(both), "operator").allowed                  # FC 23: the write is out
    assert (roles.allowed, roles.refused) == (0, 0)                          # decide() counts nothing


def test_touched_addresses_cover_what_fifo_and_file_requests_reach():
    """FC 24 reads the count at its pointer and up to 31 registers after it; FC 20 and 21 reach the
    records of each sub-request."""
    assert touched_addresses(mb.ReadFifoQueueRequest(address=99)) == [range(99, 131)]
    assert touched_addresses(mb.ReadFifoQueueRequest(address=65530)) == [range(65530, 65536)]
    assert touched_addresses(mb.ReadFileRecordRequest(records=[(4, 1, 2), (5, 150, 3)])) == \
        [range(1, 3), range(150, 153)]
    assert touched_addresses(mb.WriteFileRecordRequest(records=[(4, 98, [1, 2, 3])])) == [range(98, 101)]


def test_a_grant_bounds_fifo_and_file_records():
    guest = RoleTable({"guest": [Grant({20, 21, 24}, range(0, 100))]})
    assert not guest.decide(_pdu(mb.ReadFifoQueueRequest(address=99)), "guest").allowed  # 100..130 are out
    assert guest.decide(_pdu(mb.ReadFifoQueueRequest(address=60)), "guest").allowed      # 60..91
    assert guest.decide(_pdu(mb.ReadFileRecordRequest(records=[(4, 0, 10)])), "guest").allowed
    far_read = guest.decide(_pdu(mb.ReadFileRecordRequest(records=[(4, 0, 2), (4, 150, 2)])), "guest")
    assert not far_read.allowed and "file records 150..151" in far_read.reason
    assert not guest.decide(_pdu(mb.WriteFileRecordRequest(records=[(1, 99, [1, 2])])), "guest").allowed
    assert guest.decide(_pdu(mb.WriteFileRecordRequest(records=[(1, 98, [1, 2])])), "guest").allowed


def test_role_table_check_counts_and_logs_refusals():
    roles = RoleTable({"viewer": Grant({3}), "guest": Grant({4}, range(0, 10))}, default="guest", log_size=2)
    write = _pdu(mb.WriteSingleRegisterRequest(address=5, value=1))
    for _ in range(3):
        roles.check(write, "viewer", peer="10.0.0.9")
    assert roles.check(_pdu(mb.ReadInputRegistersRequest(address=0, count=2)), None).allowed  # default
    assert not roles.check(_pdu(mb.ReadInputRegistersRequest(address=9, count=2)), None).allowed
    assert (roles.allowed, roles.refused) == (1, 4)
    assert roles.refused_by_role == {"viewer": 3, None: 1}
    assert len(roles.log) == 2 and "10.0.0.9" in roles.log[0]
    with pytest.raises(ConfigError):
        RoleTable({"viewer": [3]})
    with pytest.raises(ConfigError):
        Grant({0})
    with pytest.raises(ConfigError):
        RoleTable({"viewer": Grant({3})}, default="nobody")


def test_a_malformed_request_in_an_allowed_function_goes_to_the_slave():
    roles = course_roles()
    assert roles.decide(bytes.fromhex("06 00"), "operator").allowed       # cut short: the slave says 03
    assert not roles.decide(bytes.fromhex("06 00"), "viewer").allowed     # not its function anyway


# --- our client, our server ---------------------------------------------------------------------------
def test_tls_round_trip_and_a_viewer_refused_a_write(secure, pki):
    server, slave, roles = secure
    operator = _master(server, pki, role="operator")
    assert operator.link.description.startswith("Modbus/TCP Security")
    operator.write_single_register(unit=1, address=3, value=4321)
    viewer = _master(server, pki, role="viewer")
    assert viewer.read_holding_registers(unit=1, address=0, count=4) == [11, 22, 33, 4321]
    with pytest.raises(ModbusExceptionError) as refused:
        viewer.write_single_register(unit=1, address=3, value=9)
    assert refused.value.code == 1
    assert slave.bank.holding_registers[3] == 4321                     # the slave never saw it
    assert server.counters.unauthorized == 1 and roles.refused == 1
    assert roles.refused_by_role["viewer"] == 1
    assert server.counters.tls_handshakes == 2 and server.counters.tls_refused == 0
    with pytest.raises(ModbusExceptionError) as far:
        operator.write_single_register(unit=1, address=500, value=9)  # outside the operator's 0..99
    assert far.value.code == 1 and server.counters.unauthorized == 2
    operator.link.close()
    viewer.link.close()


@pytest.mark.parametrize("kind, client_says, server_says", [
    ("none", "showed none", "no certificate"),
    ("foreign", "does not trust the authority", "authority that is not trusted"),
    ("expired", "expired", "has expired"),
])
def test_bad_client_certificates_get_nothing(secure, pki, kind, client_says, server_says):
    server, slave, _ = secure
    context = {"none": {"certificate": False},
               "foreign": {"cert": pki.foreign.cert, "key": pki.foreign.key},
               "expired": {"cert": pki.expired.cert, "key": pki.expired.key}}[kind]
    with pytest.raises(LinkError, match=client_says):
        master = _master(server, pki, **context)       # TLS 1.2 refuses here, TLS 1.3 at the first read
        master.write_single_register(unit=1, address=0, value=666)
    assert slave.bank.holding_registers[0] == 11
    assert _wait_for(lambda: server.counters.tls_refused == 1)
    assert server.counters.tls_handshakes == 0 and server.counters.requests == 0
    assert server_says in server.tls_log[-1]


def test_a_client_refuses_a_server_it_does_not_trust(secure, pki):
    server, _, _ = secure
    with pytest.raises(LinkError, match="not trusted"):
        mb.tcp_link(*server.address, tls=security.client_context(pki, ca=pki.foreign_ca_cert), timeout=3)
    raw = socket.create_connection(server.address, timeout=3)
    with pytest.raises(LinkError, match="another host name"):   # the certificate names 127.0.0.1
        client_handshake(security.client_context(pki), raw, "modbus.example", 3.0)


def test_plain_modbus_tcp_to_a_tls_server_is_refused(secure):
    server, slave, _ = secure
    with raw_client(server.address[1]) as sock:
        sock.sendall(mb.TcpFrame(transaction_id=1, unit=1,
                                 pdu=mb.WriteSingleRegisterRequest(address=0, value=666)).encode())
        assert is_closed_by_peer(sock)
    assert slave.bank.holding_registers[0] == 11
    assert server.counters.tls_refused == 1 and "TLS" in server.tls_log[-1]


def test_tls_to_a_plain_server_fails_with_a_message():
    with mb.TcpServer(_slave()) as plain:
        with pytest.raises(LinkError, match="TLS"):
            context = ssl.create_default_context()
            mb.tcp_link(*plain.address, tls=context, timeout=2)


# --- the defences under TLS ----------------------------------------------------------------------------
def test_a_client_that_never_handshakes_is_closed_at_the_deadline_others_are_served(pki):
    with mb.TcpServer(_slave(), tls=security.server_context(pki), handshake_timeout=0.5) as server:
        with raw_client(server.address[1]) as mute:
            start = time.monotonic()
            master = _master(server, pki, role="viewer")
            for _ in range(5):
                assert master.read_holding_registers(unit=1, address=0, count=2) == [11, 22]
            assert time.monotonic() - start < 0.5          # served while the mute one waits
            assert is_closed_by_peer(mute, timeout=3)
            assert 0.4 < time.monotonic() - start < 2.5
        assert server.counters.tls_timeouts == 1 and "no TLS handshake within 0.5 s" in server.tls_log[-1]
        assert master.read_holding_registers(unit=1, address=2, count=2) == [33, 44]
        master.link.close()


def _tls_socket(server, pki) -> ssl.SSLSocket:
    raw = socket.create_connection(server.address, timeout=3)
    return security.client_context(pki, role="viewer").wrap_socket(raw, server_hostname="127.0.0.1")


def test_slow_and_idle_clients_are_closed_under_tls(pki):
    with mb.TcpServer(_slave(), tls=security.server_context(pki), request_timeout=0.4, idle_timeout=0.6,
                      handshake_timeout=2.0) as server:
        slow, idle = _tls_socket(server, pki), _tls_socket(server, pki)
        try:
            slow.sendall(bytes.fromhex("00 01 00 00 00 06 01"))  # 7 of 12 bytes, and no more
            assert is_closed_by_peer(slow, timeout=3)
            assert is_closed_by_peer(idle, timeout=3)
        finally:
            slow.close()
            idle.close()
        assert server.counters.slow_closed == 1 and server.counters.idle_closed == 1


def test_the_connection_limit_holds_under_tls(pki):
    with mb.TcpServer(_slave(), tls=security.server_context(pki), max_connections=2) as server:
        with raw_client(server.address[1]), raw_client(server.address[1]):
            time.sleep(0.1)
            master = _master(server, pki, role="viewer")
            assert master.read_holding_registers(unit=1, address=0, count=1) == [11]
            assert server.counters.evicted >= 1 and server.connection_count <= 2
            master.link.close()


def test_unfinished_handshakes_are_evicted_before_a_client_that_finished_its_own(pki):
    """An engineer connects (its handshake done, no request yet), then 32 plain connects that never
    start a handshake fill the server: they push each other out, never the engineer."""
    with mb.TcpServer(_slave(), tls=security.server_context(pki), max_connections=4,
                      handshake_timeout=30, request_timeout=30) as server:
        master = _master(server, pki, role="engineer")
        assert _wait_for(lambda: server.counters.tls_handshakes == 1)
        plain = []
        try:
            for _ in range(32):
                plain.append(socket.create_connection(server.address[:2]))
                time.sleep(0.005)
            assert _wait_for(lambda: server.counters.evicted >= 29)
            assert master.read_holding_registers(unit=1, address=0, count=1) == [11]
            # on its first connection: the link did not have to connect (and shake hands) again
            assert server.counters.tls_handshakes == 1 and server.counters.connections == 33
        finally:
            for sock in plain:
                sock.close()
            master.link.close()


def test_pipelined_requests_over_tls_are_all_answered(secure, pki):
    server, _, _ = secure
    sock = _tls_socket(server, pki)
    try:
        frames = b"".join(mb.TcpFrame(transaction_id=i, unit=1,
                                      pdu=mb.ReadHoldingRegistersRequest(address=0, count=100)).encode()
                          for i in range(300))
        sock.sendall(frames)
        tids = [int.from_bytes(recv_frame(sock)[:2], "big") for _ in range(300)]
        assert tids == list(range(300))
    finally:
        sock.close()


# --- with pymodbus ----------------------------------------------------------------------------------------
def test_pymodbus_tls_client_reads_our_tls_server(secure, pki):
    server, slave, _ = secure
    context = security.client_context(pki, role="operator")
    context.check_hostname = False  # pymodbus 3.16 sync: no server_hostname given; the chain is checked
    client = ModbusTlsClient(HOST, port=server.address[1], sslctx=context, timeout=3, retries=0)
    assert client.connect()
    try:
        assert client.read_holding_registers(0, count=4, device_id=1).registers == [11, 22, 33, 44]
        assert not client.write_register(2, 777, device_id=1).isError()
        assert slave.bank.holding_registers[2] == 777
        refused = client.write_register(200, 1, device_id=1)          # outside the operator's 0..99
        assert refused.isError() and refused.exception_code == 1
    finally:
        client.close()
    assert server.counters.tls_handshakes == 1 and server.counters.unauthorized == 1


def test_our_tls_link_reads_pymodbus_tls_server(pki):
    device = pymodbus_device(holding=[5, 6, 7])
    with PymodbusServer(device, sslctx=security.server_context(pki)) as peer:
        link = mb.tcp_link(HOST, peer.port, tls=security.client_context(pki), timeout=3)
        master = mb.Master(link, timeout=3)
        try:
            assert master.read_holding_registers(unit=1, address=0, count=3) == [5, 6, 7]
            master.write_single_register(unit=1, address=1, value=99)
            assert master.read_holding_registers(unit=1, address=1, count=1) == [99]
        finally:
            link.close()


# --- the command line ------------------------------------------------------------------------------------
def _cli(*args: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "modbus_edu", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})


def _bound_port(proc: subprocess.Popen, seconds: float = 20) -> tuple[str, int]:
    ready, _, _ = select.select([proc.stdout], [], [], seconds)
    assert ready, "the command printed nothing in time"
    line = proc.stdout.readline()
    assert "127.0.0.1:" in line, line + proc.stderr.read()
    return line, int(line.split("127.0.0.1:")[1].split(" ")[0].rstrip(";"))


def _stop(proc: subprocess.Popen) -> str:
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=15)
    assert proc.returncode == 0 and "Traceback" not in err, err
    return out


def _tls_args(pair_cert, pair_key, ca) -> list[str]:
    return ["--tls-cert", str(pair_cert), "--tls-key", str(pair_key), "--tls-ca", str(ca)]


def test_cli_serve_and_poll_speak_modbus_tcp_security(pki, capsys):
    from modbus_edu.cli import main

    proc = _cli("serve", "bank", "--tcp", "0", *_tls_args(pki.server_cert, pki.server_key, pki.ca_cert))
    try:
        line, port = _bound_port(proc)
        assert "Modbus/TCP Security (TLS)" in line
        client = _tls_args(pki.roles["viewer"].cert, pki.roles["viewer"].key, pki.ca_cert)
        status = main(["poll", "--tcp", f"127.0.0.1:{port}", "--address", "2", "--count", "3",
                       "--polls", "1", *client])
        out = capsys.readouterr().out
        assert status == 0 and "[2] 2  [3] 3  [4] 4" in out, out      # bank: register n holds n
        with pytest.raises(LinkError, match="showed none"):        # a client without a certificate
            master = mb.Master(mb.tcp_link("127.0.0.1", port, tls=security.client_context(
                pki, certificate=False)), timeout=2)
            master.read_holding_registers(unit=1, address=0, count=1)
    finally:
        if proc.poll() is None:
            _stop(proc)


@pytest.mark.parametrize("args, message", [
    (["--tls-cert", "x.crt"], "--tls-key, --tls-ca missing"),
    (["--serial", "loop://", "--tls-cert", "a", "--tls-key", "b", "--tls-ca", "c"], "not a serial line"),
])
def test_cli_tls_options_go_together(args, message, capsys):
    from modbus_edu.cli import main

    assert main(["serve", "bank", *args]) != 0
    assert message in capsys.readouterr().err


def test_cli_gateway_serves_tls_in_front_of_a_serial_line(pki):
    from modbus_edu.links.serial import SerialServer, TcpSerialPort

    with SerialServer(_slave(), TcpSerialPort("127.0.0.1", 0)) as behind:
        serial_url = f"socket://127.0.0.1:{behind.port.address[1]}"
        proc = _cli("gateway", "--tcp", "127.0.0.1:0", "--serial", serial_url,
                    *_tls_args(pki.server_cert, pki.server_key, pki.ca_cert))
        try:
            line, port = _bound_port(proc)
            assert "Modbus/TCP Security (TLS)" in line
            master = _master(type("S", (), {"address": ("127.0.0.1", port)}), pki, role="viewer")
            assert master.read_holding_registers(unit=1, address=0, count=2) == [11, 22]
            master.link.close()
        finally:
            if proc.poll() is None:
                _stop(proc)


def test_a_refused_client_does_not_connect_again_by_itself(pki):
    # the server's alert is already waiting when the first request goes: the link says so, once
    with mb.TcpServer(_slave(), tls=security.server_context(pki)) as server:
        link = mb.tcp_link(*server.address, tls=security.client_context(pki, certificate=False), timeout=3)
        time.sleep(0.2)
        with pytest.raises(LinkError, match="showed none"):
            mb.Master(link, timeout=2).write_single_register(unit=1, address=0, value=1)
        assert link.reconnects == 0
    assert server.counters.tls_refused == 1


def test_load_roles_reads_a_json_table_and_names_what_is_wrong(tmp_path):
    path = tmp_path / "roles.json"
    path.write_text('{"roles": {"viewer": [{"functions": [3, 4]}], '
                    '"operator": [{"functions": [6], "addresses": [0, 99]}]}, "default": "viewer"}')
    roles = security.load_roles(path)
    assert roles.decide(_pdu(mb.WriteSingleRegisterRequest(address=99, value=1)), "operator").allowed
    assert not roles.decide(_pdu(mb.WriteSingleRegisterRequest(address=100, value=1)), "operator").allowed
    assert roles.decide(_pdu(mb.ReadInputRegistersRequest(address=0, count=1)), None).allowed  # default
    assert "operator FC 6 at 0..99" in roles.describe()
    for text, words in [("{", "not JSON"), ('{"viewer": []}', '"roles"'),
                        ('{"roles": {"viewer": [{"functions": [3], "addresses": [5, 2]}]}}', "[first, last]"),
                        ('{"roles": {"viewer": [{"function": [3]}]}}', "a grant is")]:
        path.write_text(text)
        with pytest.raises(ConfigError, match=words):
            security.load_roles(path)
