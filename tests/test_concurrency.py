"""Many clients at once: every answer correct and matched to its request.

50 client threads x 200 requests each against one TcpServer.  Thread ``i`` owns holding register
``i``: it writes a value there and reads it back, alternately, so a response delivered to the wrong
client, or an answer to the wrong request, shows as a wrong value.  Transaction ids are unique per
thread (``i * 1000 + j``), so the match is checked on the id too.
"""

from __future__ import annotations

import socket
import threading

from conftest_io import HOST, recv_frame

from modbus_edu.framing import TcpFrame
from modbus_edu.links.tcp import TcpServer, tcp_link
from modbus_edu.master import Master
from modbus_edu.pdu import (
    ReadHoldingRegistersRequest,
    ReadHoldingRegistersResponse,
    WriteSingleRegisterRequest,
    WriteSingleRegisterResponse,
)
from modbus_edu.slave import Slave

THREADS = 50
REQUESTS = 200


def _client(port: int, index: int, errors: list[str], barrier: threading.Barrier) -> None:
    try:
        with socket.create_connection((HOST, port), timeout=10) as sock:
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            barrier.wait(10)  # everybody starts together
            for j in range(REQUESTS):
                tid = index * 1000 + j
                value = (index * 1000 + j) & 0xFFFF
                if j % 2 == 0:
                    pdu = WriteSingleRegisterRequest(address=index, value=value)
                    expected = WriteSingleRegisterResponse(address=index, value=value)
                else:
                    pdu = ReadHoldingRegistersRequest(address=index, count=1)
                    # the value this thread wrote one request earlier, and nobody else touches
                    expected = ReadHoldingRegistersResponse(registers=((index * 1000 + j - 1) & 0xFFFF,))
                sock.sendall(TcpFrame(transaction_id=tid, unit=1, pdu=pdu).encode())
                answer = TcpFrame.decode(recv_frame(sock), role="response")
                if answer.transaction_id != tid or answer.unit != 1 or answer.pdu != expected:
                    errors.append(f"thread {index} request {j}: sent tid {tid}, got {answer}")
                    return
    except Exception as exc:  # noqa: BLE001 - reported by the test
        errors.append(f"thread {index}: {exc!r}")


def test_fifty_clients_two_hundred_requests_each():
    slave = Slave()
    with TcpServer(slave, max_connections=THREADS + 5) as server:
        errors: list[str] = []
        barrier = threading.Barrier(THREADS)
        threads = [
            threading.Thread(target=_client, args=(server.address[1], i, errors, barrier))
            for i in range(THREADS)
        ]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(60)
        assert not any(t.is_alive() for t in threads), "some clients never finished"
        assert errors == []
        counters = server.counters
        assert counters.connections == THREADS
        assert counters.requests == counters.responses == THREADS * REQUESTS
        assert counters.bad_frames == counters.evicted == 0
    # each thread's last write is in its own register
    assert slave.bank.holding_registers.read(0, THREADS) == [
        (i * 1000 + REQUESTS - 2) & 0xFFFF for i in range(THREADS)
    ]


def test_masters_in_threads_each_on_its_own_tcp_link():
    slave = Slave()
    errors: list[str] = []

    def run(index: int) -> None:
        try:
            with tcp_link(*server.address) as link:
                master = Master(link, timeout=5.0, transaction_id=index * 100)
                for j in range(50):
                    master.write_multiple_registers(unit=1, address=10 * index, values=[index, j, j + 1])
                    got = master.read_holding_registers(unit=1, address=10 * index, count=3)
                    if got != [index, j, j + 1]:
                        errors.append(f"master {index}: {got}")
                        return
                if master.stats.mismatches or master.stats.timeouts:
                    errors.append(f"master {index}: {master.stats.summary()}")
        except Exception as exc:  # noqa: BLE001
            errors.append(f"master {index}: {exc!r}")

    with TcpServer(slave) as server:
        threads = [threading.Thread(target=run, args=(i,)) for i in range(10)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(60)
    assert errors == []
    assert slave.counters.requests == 10 * 100
