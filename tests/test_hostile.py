"""A TCP port is open to whatever connects: the server must survive bad clients and keep serving others.

Throughout each test a well-behaved client keeps its connection and is answered before and after the
misbehaviour.  All traffic on 127.0.0.1; idle timeouts are short so that nothing waits long.
"""

from __future__ import annotations

import random
import socket
import struct
import threading
import time

import pytest
from conftest_io import HOST, is_closed_by_peer, raw_client, recv_frame

from modbus_edu.framing import TcpFrame
from modbus_edu.links.tcp import TcpServer
from modbus_edu.pdu import ReadHoldingRegistersRequest
from modbus_edu.slave import Slave


def request(tid: int, address: int = 0, count: int = 1, unit: int = 1) -> bytes:
    pdu = ReadHoldingRegistersRequest(address=address, count=count)
    return TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()


def ask(sock: socket.socket, tid: int, address: int = 0) -> tuple[int, ...]:
    sock.sendall(request(tid, address))
    frame = TcpFrame.decode(recv_frame(sock), role="response")
    assert frame.transaction_id == tid
    return frame.pdu.registers


@pytest.fixture
def server():
    slave = Slave()
    slave.bank.holding_registers.write(0, list(range(100, 200)))
    with TcpServer(slave, idle_timeout=0.5, max_connections=8) as srv:
        yield srv
    assert not srv.running


@pytest.fixture
def good(server):
    """A well-behaved client, connected for the whole test."""
    with raw_client(server.address[1]) as sock:
        assert ask(sock, 1) == (100,)
        yield sock


MALFORMED = {
    "length 0": struct.pack(">HHHB", 1, 0, 0, 1),
    "length 1: a unit id and no function code": struct.pack(">HHHB", 1, 0, 1, 1),
    "length 300: longer than any PDU": struct.pack(">HHHB", 1, 0, 300, 1),
    "protocol id 1": struct.pack(">HHHB", 1, 1, 6, 1) + bytes.fromhex("0300000001"),
    "protocol id 0xFFFF": struct.pack(">HHHB", 1, 0xFFFF, 6, 1) + bytes.fromhex("0300000001"),
}


@pytest.mark.parametrize("what", list(MALFORMED))
def test_malformed_mbap_closes_that_connection_only(server, good, what):
    header = MALFORMED[what]
    with raw_client(server.address[1]) as bad:
        bad.sendall(header)
        assert is_closed_by_peer(bad), what
    assert ask(good, 2, 5) == (105,)
    assert server.counters.bad_frames == 1


def test_valid_frames_before_the_bad_header_are_still_answered(server, good):
    with raw_client(server.address[1]) as bad:
        bad.sendall(request(7) + struct.pack(">HHHB", 8, 3, 6, 1))
        frame = TcpFrame.decode(recv_frame(bad), role="response")
        assert frame.transaction_id == 7
        assert is_closed_by_peer(bad)
    assert ask(good, 3) == (100,)


def test_random_garbage_is_closed_and_others_keep_being_served(server, good):
    rng = random.Random(1234)
    for round_ in range(5):
        junk = bytes(rng.randrange(256) for _ in range(rng.randrange(8, 200)))
        with raw_client(server.address[1]) as bad:
            bad.sendall(junk)
            # closed at once for a bad header (or, should the junk pass for the start of a frame,
            # after the idle timeout)
            assert is_closed_by_peer(bad, timeout=3.0)
        assert ask(good, 10 + round_, round_) == (100 + round_,)
    assert server.counters.bad_frames + server.counters.idle_closed == 5


def test_http_request_on_the_modbus_port_is_closed(server, good):
    with raw_client(server.address[1]) as bad:
        bad.sendall(b"GET / HTTP/1.1\r\nHost: plc\r\n\r\n")  # 'GE' 'T ' '/ ': protocol id 0x5420
        assert is_closed_by_peer(bad)
    assert ask(good, 4) == (100,)


def test_half_a_frame_then_silence_is_closed_by_the_idle_timeout(server, good):
    with raw_client(server.address[1]) as bad:
        bad.sendall(request(1)[:5])
        started = time.monotonic()
        # meanwhile the good client is served
        assert ask(good, 5) == (100,)
        assert is_closed_by_peer(bad, timeout=3.0)
        assert time.monotonic() - started >= 0.4
    assert server.counters.idle_closed >= 1


def test_silent_client_is_closed_by_the_idle_timeout(server):
    with raw_client(server.address[1]) as idle:
        assert is_closed_by_peer(idle, timeout=3.0)
    assert server.counters.idle_closed == 1


def test_slow_sender_one_byte_at_a_time_is_answered(server, good):
    # 12 bytes with 30 ms pauses: 0.36 s in all, each pause well under the 0.5 s idle timeout
    with raw_client(server.address[1]) as slow:
        frame = request(42, 9)
        for i, byte in enumerate(frame):
            slow.sendall(bytes([byte]))
            time.sleep(0.03)
            if i == 6:  # halfway through, the good client is served without waiting
                assert ask(good, 6) == (100,)
        answer = TcpFrame.decode(recv_frame(slow), role="response")
        assert answer.transaction_id == 42 and answer.pdu.registers == (109,)
    assert server.counters.bad_frames == 0


def test_at_the_connection_limit_the_longest_idle_client_makes_room(server, good):
    port = server.address[1]
    extra = [socket.create_connection((HOST, port), timeout=2) for _ in range(7)]  # 1 + 7 = 8 = limit
    try:
        for i, sock in enumerate(extra):
            assert ask(sock, 100 + i, i) == (100 + i,)
        assert ask(good, 7) == (100,)  # now extra[0] has been idle longest
        with raw_client(port) as newcomer:
            assert ask(newcomer, 200) == (100,)  # served, not refused
        assert server.counters.evicted == 1
        assert is_closed_by_peer(extra[0])
        assert ask(good, 8) == (100,)
    finally:
        for sock in extra:
            sock.close()


def test_client_that_never_reads_does_not_block_others(server, good):
    with raw_client(server.address[1]) as greedy:
        greedy.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        # 4000 requests for 125 registers each (1 MB of answers), none of them read: the server stops
        # answering this client once 64 KiB are waiting, and keeps serving the others meanwhile
        burst = request(1, 0, 125) * 4000
        threading.Thread(target=_send_quietly, args=(greedy, burst), daemon=True).start()
        for i in range(20):
            assert ask(good, 300 + i, i) == (100 + i,)
    assert ask(good, 400) == (100,)


def _send_quietly(sock: socket.socket, data: bytes) -> None:
    try:
        sock.sendall(data)
    except OSError:
        pass


def test_connection_reset_mid_frame(server, good):
    bad = socket.create_connection((HOST, server.address[1]), timeout=2)
    bad.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    bad.sendall(request(1)[:9])
    bad.close()  # linger 0: an RST instead of a goodbye
    assert ask(good, 8) == (100,)


def test_clean_shutdown_with_clients_attached():
    slave = Slave()
    server = TcpServer(slave, idle_timeout=None).start()
    port = server.address[1]
    clients = [socket.create_connection((HOST, port), timeout=2) for _ in range(5)]
    try:
        for i, sock in enumerate(clients):
            assert ask(sock, i) == (0,)
        clients[0].sendall(request(99)[:4])  # one of them in the middle of a frame
        thread = server._thread
        server.close()
        assert thread is not None and not thread.is_alive()
        assert not server.running and server.connection_count == 0
        for sock in clients:
            assert is_closed_by_peer(sock)
        with pytest.raises(ConnectionRefusedError):
            socket.create_connection((HOST, port), timeout=1).close()
    finally:
        for sock in clients:
            sock.close()
