"""The slave's fast path for Modbus/TCP reads (``Pdu.answer_from_bytes``) against the general way.

Two slaves with the same bank hear the same seeded stream of frames, well-formed and broken (bad MBAP
lengths and protocol ids, truncated and padded PDUs, unknown and exception function codes, quantities and
addresses out of range, other units, broadcast, unit 0 and 0xFF to the device itself, writes, FC 8's
listen-only mode and restart, FC 11 and FC 12): one takes the fast path where it can, the other never does.
Every answer, every counter, the FC 11 event counter, the FC 12 event log and the traffic log's text must
be the same, frame after frame.
"""

from __future__ import annotations

import random
import socket
import struct

import pytest

from modbus_edu.datamodel import DataBank, Table
from modbus_edu.devices import PowerMeter
from modbus_edu.framing import TcpFrame
from modbus_edu.links.tcp import TcpServer, tcp_link
from modbus_edu.master import Master
from modbus_edu.pdu import REQUEST_CLASSES, Pdu, ReadCoilsRequest, ReadHoldingRegistersRequest
from modbus_edu.slave import Slave

FRAMES = 12_000


class GeneralSlave(Slave):
    """A slave that never takes the fast path: the reference."""

    def _answer_quickly(self, frame: bytes) -> None:
        return None


def _bank(sparse: bool, rng: random.Random) -> DataBank:
    bank = DataBank(sparse=sparse)
    for table in bank.tables:
        if sparse:
            for _ in range(6):
                start = rng.randrange(0, 65536 - 300)
                table.declare(start, rng.randrange(1, 300))
            table.declare(0, 200)
            table.declare(65400, 136)
        for address in table.addresses()[:300] if sparse else range(0, 65536, 97):
            table[address] = rng.randrange(2) if table.is_bits else rng.randrange(65536)
        if not sparse:
            table.write(65500, [1] * 36)
    return bank


def _read_pdu(rng: random.Random) -> bytes:
    function = rng.choice((1, 2, 3, 4))
    limit = 2000 if function <= 2 else 125
    count = rng.choice((1, 2, 7, 8, 9, 10, limit, limit + 1, 0, rng.randrange(0, 65536),
                        rng.randrange(1, limit + 1)))
    address = rng.choice((0, 5, 199, 65535, 65536 - count if count <= 65536 else 0, 65400, 65500,
                          rng.randrange(65536)))
    pdu = struct.pack(">BHH", function, address & 0xFFFF, count & 0xFFFF)
    shape = rng.random()
    if shape < 0.04:
        return pdu[:rng.randrange(1, 5)]  # truncated
    if shape < 0.08:
        return pdu + bytes(rng.randrange(1, 4))  # trailing bytes
    return pdu


def _other_pdu(rng: random.Random) -> bytes:
    kind = rng.random()
    if kind < 0.15:
        return struct.pack(">BHH", 6, rng.randrange(300), rng.randrange(65536))
    if kind < 0.25:
        return struct.pack(">BHH", 5, rng.randrange(300), rng.choice((0xFF00, 0, 0x1234)))
    if kind < 0.35:
        values = [rng.randrange(65536) for _ in range(rng.randrange(1, 5))]
        return struct.pack(f">BHHB{len(values)}H", 16, rng.randrange(300), len(values), 2 * len(values),
                           *values)
    if kind < 0.45:
        sub = rng.choice((0x00, 0x01, 0x01, 0x04, 0x0A, 0x0B, 0x0D, 0x02))
        value = 0xFF00 if sub == 0x01 and rng.random() < 0.5 else 0
        return struct.pack(">BHH", 8, sub, value)
    if kind < 0.55:
        return bytes((rng.choice((0x0B, 0x0C)),))
    if kind < 0.65:
        return bytes((rng.choice((0, 0x30, 0x41, 0x7F, 0x80, 0x83, 0xFF)),)) + bytes(rng.randrange(5))
    if kind < 0.75:
        return bytes((0x17,)) + bytes(rng.randrange(0, 12))
    return bytes(rng.randrange(256) for _ in range(rng.randrange(1, 12)))


def _frame(rng: random.Random, tid: int) -> bytes:
    pdu = _read_pdu(rng) if rng.random() < 0.7 else _other_pdu(rng)
    unit = rng.choice((1, 1, 1, 1, 0, 0xFF, 2, 247, 248))
    length = len(pdu) + 1
    protocol = 0
    shape = rng.random()
    if shape < 0.03:
        length = rng.choice((0, 1, length - 1, length + 1, 255, 0xFFFF))
    elif shape < 0.05:
        protocol = rng.choice((1, 0x100, 0xFFFF))
    frame = struct.pack(">HHHB", tid, protocol, length & 0xFFFF, unit) + pdu
    if rng.random() < 0.01:
        frame = frame[:rng.randrange(0, 8)]  # not even a header
    return frame


def _state(slave: Slave) -> tuple:
    return (slave.counters.as_dict(), slave.event_count, list(slave.events), slave.listen_only,
            slave.diagnostic_counters())


@pytest.mark.parametrize("unit, sparse, seed", [(1, False, 1), (1, True, 2), (None, False, 3)])
def test_fast_and_general_paths_agree_frame_by_frame(unit, sparse, seed):
    rng = random.Random(seed)
    fast = Slave(unit=unit, bank=_bank(sparse, random.Random(seed)))
    general = GeneralSlave(unit=unit, bank=_bank(sparse, random.Random(seed)))
    assert fast.bank == general.bank
    answered_fast = 0
    for tid in range(FRAMES // 3):
        frame = _frame(rng, tid)
        direct = rng.random() < 0.1
        if direct:
            answers = fast.handle_direct(frame), general.handle_direct(frame)
        else:
            answers = fast.handle(frame, "tcp"), general.handle(frame, "tcp")
        assert answers[0] == answers[1], (frame.hex(" "), [a and a.hex(" ") for a in answers])
        assert _state(fast) == _state(general), frame.hex(" ")
        answered_fast += fast.log._entries[-1][6].__class__ is tuple
    assert fast.bank == general.bank
    assert fast.log.to_text() == general.log.to_text()
    assert [entry.note for entry in fast.log] == [entry.note for entry in general.log]
    assert answered_fast > FRAMES // 30, "the fast path was hardly taken: the test no longer tests it"


def test_the_log_writes_a_fast_answer_note_when_read():
    slave = Slave(unit=1)
    slave.bank.coils.write(0, [True, False, True])
    request = TcpFrame(transaction_id=7, unit=1, pdu=ReadCoilsRequest(address=0, count=3)).encode()
    answer = slave.handle(request, "tcp")
    assert answer == bytes.fromhex("0007 0000 0004 01 01 01 05")
    assert slave.log._entries[-1][6] == (request[7:], answer[7:])  # kept as bytes until read
    assert slave.log[-1].note == "Read Coils response: bits 101"  # the 3 bits asked for, no padding
    slave.log.annotate("seen")
    assert slave.log[-1].note == "Read Coils response: bits 101; seen"


def test_the_fast_path_steps_aside_for_hooks_subclasses_and_custom_banks():
    request = TcpFrame(transaction_id=1, unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=2)).encode()
    calls = []
    hooked = Slave(unit=1, on_read=lambda slave, kind, address, count: calls.append((kind, address, count)))
    assert hooked._answer_quickly(request) is None
    hooked.handle(request, "tcp")
    assert calls == [("holding_registers", 0, 2)]

    meter = PowerMeter(unit=1)  # overrides process and before_read: measures when asked
    assert meter._answer_quickly(request) is None

    class Doubling(Table):
        def read(self, address, count=1):
            return [2 * v for v in super().read(address, count)]

    bank = DataBank()
    bank.holding_registers = Doubling("holding_registers")
    bank.holding_registers.write(0, [1, 2])
    custom = Slave(unit=1, bank=bank)
    assert custom._answer_quickly(request) is None
    assert custom.handle(request, "tcp")[-4:] == bytes.fromhex("0002 0004")

    listening = Slave(unit=1)
    listening.listen_only = True
    assert listening._answer_quickly(request) is None
    plain = Slave(unit=1)
    assert plain._answer_quickly(request) is not None


def test_every_read_function_has_its_fast_path_in_its_class():
    for function in (1, 2, 3, 4):
        cls = REQUEST_CLASSES[function]
        assert cls.answer_from_bytes.__func__ is not Pdu.answer_from_bytes.__func__
        assert cls.answer_from_bytes(bytes((function, 0, 0, 0, 1)), DataBank()) is not None
    assert REQUEST_CLASSES[6].answer_from_bytes(bytes((6, 0, 0, 0, 1)), DataBank()) is None


def test_a_tcp_server_answers_reads_through_the_fast_path_and_counts_them():
    slave = Slave(unit=1)
    slave.bank.holding_registers.write(0, [11, 22, 33])
    with TcpServer(slave) as server:
        master = Master(tcp_link(*server.address, timeout=5))
        try:
            for _ in range(5):
                assert master.read_holding_registers(unit=1, address=0, count=3) == [11, 22, 33]
        finally:
            master.link.close()
        with socket.create_connection(server.address, timeout=5) as sock:
            sock.sendall(bytes.fromhex("0009 0000 0006 01 03 0000 007E"))  # 126 registers: exception 03
            answer = b""
            while len(answer) < 9:
                answer += sock.recv(9 - len(answer))
        assert answer == bytes.fromhex("0009 0000 0003 01 83 03")
        assert server.counters.requests == server.counters.responses == 6
    assert slave.counters.requests == 6 and slave.counters.exceptions == 1
    assert slave.event_count == 5
    notes = [entry.note for entry in slave.log if entry.direction == "tx"]
    assert notes[0] == "Read Holding Registers response: registers [11, 22, 33]"
    assert notes[-1].startswith("Exception response")
