"""A TcpServer holds a bounded number of bytes for each client, in every framing, whatever it sends;
RTU over TCP answers what the specification answers; a flood of broken connections costs a served
client nothing.

Memory is asserted as the server's own count of buffered bytes (``TcpServer.buffered_bytes``), not as
the process's size: the claim is that the server stops reading a client that does not keep up, and
TCP's flow control then holds that client back.
"""

from __future__ import annotations

import socket
import struct
import time

import pytest
from conftest_io import HOST, raw_client

import modbus_edu as mb
from modbus_edu.crc import crc16
from modbus_edu.links.tcp import TcpServer

BOUND = TcpServer.MAX_BUFFERED_PER_CONNECTION


def _request(framing: str, tid: int = 1, unit: int = 1) -> bytes:
    pdu = mb.ReadHoldingRegistersRequest(address=0, count=10)
    if framing == "tcp":
        return mb.TcpFrame(transaction_id=tid, unit=unit, pdu=pdu).encode()
    frame = mb.RtuFrame if framing == "rtu" else mb.AsciiFrame
    return frame(unit=unit, pdu=pdu).encode()


def _flood(sock: socket.socket, data: bytes, seconds: float) -> int:
    """Send ``data`` over and over without reading, for ``seconds`` or until the peer stops taking it."""
    sock.setblocking(False)
    sent = 0
    end = time.monotonic() + seconds
    stalled_since = None
    while time.monotonic() < end:
        try:
            sent += sock.send(data)
            stalled_since = None
        except BlockingIOError:
            stalled_since = stalled_since or time.monotonic()
            if time.monotonic() - stalled_since > 0.3:  # the server stopped reading us: flow control
                break
            time.sleep(0.005)
    sock.setblocking(True)
    return sent


def _ask(sock: socket.socket, framing: str, tid: int = 9) -> bytes:
    sock.sendall(_request(framing, tid))
    sock.settimeout(2.0)
    data = b""
    want = {"tcp": 9 + 20, "rtu": 5 + 20, "ascii": 11 + 40}[framing]
    while len(data) < want:
        chunk = sock.recv(want - len(data))
        assert chunk, "the server closed a well-behaved client"
        data += chunk
    return data


@pytest.mark.parametrize("framing", ["tcp", "rtu", "ascii"])
def test_clients_that_pipeline_without_reading_are_held_back_and_a_bystander_is_served(framing):
    with TcpServer(mb.Slave(unit=1), framing=framing) as server:
        port = server.address[1]
        burst = _request(framing) * 2000
        flooders = [socket.create_connection((HOST, port)) for _ in range(10)]
        try:
            with raw_client(port) as bystander:
                sent = sum(_flood(sock, burst, 1.5) for sock in flooders)
                buffered = server.buffered_bytes
                start = time.monotonic()
                _ask(bystander, framing)
                waited = time.monotonic() - start
        finally:
            for sock in flooders:
                sock.close()
        assert buffered <= 11 * BOUND, f"{buffered} bytes buffered for 10 clients that sent {sent}"
        assert server.counters.held_back >= 10
        assert waited < 1.0, f"the bystander waited {waited:.2f} s"


@pytest.mark.parametrize("framing", ["tcp", "rtu"])
def test_a_client_that_pipelines_and_reads_is_answered_in_order_with_bounded_buffers(framing):
    with TcpServer(mb.Slave(unit=1), framing=framing) as server, raw_client(server.address[1]) as sock:
        requests = b"".join(_request(framing, tid) for tid in range(1, 3001))
        sock.setblocking(False)
        out, got, peak = memoryview(requests), bytearray(), 0
        end = time.monotonic() + 20
        size = 29 if framing == "tcp" else 25
        while len(got) < 3000 * size and time.monotonic() < end:
            if out:
                try:
                    out = out[sock.send(out[:65536]):]
                except BlockingIOError:
                    pass
            try:
                got += sock.recv(65536)
            except BlockingIOError:
                time.sleep(0.001)
            peak = max(peak, server.buffered_bytes)
        assert len(got) == 3000 * size
        if framing == "tcp":
            tids = [int.from_bytes(got[i:i + 2], "big") for i in range(0, len(got), size)]
            assert tids == list(range(1, 3001))
        assert peak <= BOUND


def _rtu(hexs: str) -> bytes:
    body = bytes.fromhex(hexs)
    return body + crc16(body).to_bytes(2, "little")


@pytest.mark.parametrize("request_hex, answer", [
    ("01 08 0000 1234 5678", "01 08 0000 1234 5678"),          # Return Query Data, two words: echoed
    ("01 08 0000 1234 5678 9ABC DEF0", "01 08 0000 1234 5678 9ABC DEF0"),
    ("01 41 0001", "01 C1 01"),                                 # a function nobody implements: 01
    ("01 10 0000 0002 03 0001 00", "01 90 03"),                 # byte count 3 for 2 registers: 03
], ids=["FC 8/00 two words", "FC 8/00 four words", "unknown function", "FC 16 byte count"])
def test_rtu_over_tcp_answers_what_the_spec_answers(request_hex, answer):
    with TcpServer(mb.Slave(unit=1), framing="rtu") as server, raw_client(server.address[1]) as sock:
        expected = _rtu(answer)
        sock.sendall(_rtu(request_hex))
        sock.settimeout(2.0)
        got = b""
        while len(got) < len(expected):
            chunk = sock.recv(256)
            assert chunk
            got += chunk
        assert got == expected


def test_rtu_over_tcp_ends_an_unfinished_frame_at_a_quiet_gap():
    with TcpServer(mb.Slave(unit=1), framing="rtu", quiet_gap=0.03) as server, \
            raw_client(server.address[1]) as sock:
        sock.sendall(_rtu("01 10 0000 0002 04 0001 0002")[:7])  # a write cut short: never completed
        time.sleep(0.1)
        assert _ask(sock, "rtu") == mb.RtuFrame(
            unit=1, pdu=mb.ReadHoldingRegistersResponse(registers=[0] * 10)).encode()


def test_junk_shaped_like_long_fc16_requests_is_closed_and_costs_others_nothing():
    junk = b"".join(bytes([1, 0x10, 0, 0, 0, 0x7B, 0xF6]) + bytes(range(40, 240)) for _ in range(50))
    with TcpServer(mb.Slave(unit=1), framing="rtu") as server:
        port = server.address[1]
        with raw_client(port) as bystander:
            bad = [socket.create_connection((HOST, port)) for _ in range(5)]
            try:
                worst = 0.0
                for _ in range(3):
                    for sock in bad:
                        try:
                            sock.sendall(junk)
                        except OSError:
                            pass
                    start = time.monotonic()
                    _ask(bystander, "rtu")
                    worst = max(worst, time.monotonic() - start)
                end = time.monotonic() + 10
                while server.counters.bad_frames < 5 and time.monotonic() < end:
                    time.sleep(0.05)  # the server reads junk a little at a time, between others' turns
            finally:
                for sock in bad:
                    sock.close()
        assert worst < 1.0, f"a bystander waited {worst:.2f} s behind junk"
        assert server.counters.bad_frames >= 5


def test_two_hundred_connections_reset_mid_frame_leave_a_served_client_alone():
    with TcpServer(mb.Slave(unit=1), max_connections=32) as server:
        port = server.address[1]
        with raw_client(port) as bystander:
            assert _ask(bystander, "tcp", 1)
            for i in range(200):
                sock = socket.create_connection((HOST, port))
                sock.sendall(_request("tcp", i)[:5])
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
                sock.close()  # a reset, mid-frame
            assert _ask(bystander, "tcp", 2)


def _open_after(socks: list[socket.socket], payloads: list[bytes], interval: float, seconds: float) -> int:
    """Send each socket its payload one byte per ``interval`` for ``seconds``; how many the server has
    not closed by then (a closed one reads as end of file or a reset)."""
    for sock in socks:
        sock.setblocking(False)
    closed: set[int] = set()
    end = time.monotonic() + seconds
    at = 0
    while time.monotonic() < end:
        for i, sock in enumerate(socks):
            if i in closed:
                continue
            try:
                if sock.recv(64) == b"":
                    closed.add(i)
                    continue
            except BlockingIOError:
                pass
            except OSError:
                closed.add(i)
                continue
            try:
                sock.send(payloads[i][at % len(payloads[i]):at % len(payloads[i]) + 1])
            except OSError:
                closed.add(i)
        at += 1
        time.sleep(interval)
    return len(socks) - len(closed)


@pytest.mark.parametrize("framing", ["rtu", "ascii"])
def test_rtu_and_ascii_trickled_frames_and_lone_junk_bytes_close_within_the_request_timeout(framing):
    """Ten clients trickle a 109-byte FC 16 request at one byte per 0.1 s, and one sends a 0xFF every
    0.5 s: all are closed once request_timeout has passed since their first byte, and counted."""
    frame = (mb.RtuFrame if framing == "rtu" else mb.AsciiFrame)(
        unit=1, pdu=mb.WriteMultipleRegistersRequest(address=0, values=list(range(50)))).encode()
    with TcpServer(mb.Slave(unit=1), framing=framing, request_timeout=1.0, idle_timeout=60) as server:
        port = server.address[1]
        with raw_client(port) as bystander:
            socks = [socket.create_connection((HOST, port)) for _ in range(11)]
            try:
                still_open = _open_after(socks[:10], [frame] * 10, 0.1, 2.5)
                assert _ask(bystander, framing)  # the bystander is served meanwhile, and stays
                junk_open = _open_after(socks[10:], [b"\xff"], 0.5, 2.5)
            finally:
                for sock in socks:
                    sock.close()
        assert (still_open, junk_open) == (0, 0)
        assert server.counters.slow_closed == 11
