"""FC 7, 17, 22 and 23: the spec's examples, every rule, and pymodbus 3.16 both ways (bytes and live)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pymodbus.client import ModbusTcpClient
from pymodbus.framer import FramerRTU, FramerSocket
from pymodbus.pdu import DecodePDU
from pymodbus.pdu import other_message as po
from pymodbus.pdu import register_message as pr

import modbus_edu as mb
from modbus_edu import pdu as P
from modbus_edu.errors import ByteCountError, QuantityError, ValueRangeError

REGS = st.integers(0, 0xFFFF)


def test_the_specifications_examples():
    # FC 22: register 4 holds 0x12; AND 0xF2, OR 0x25 -> 0x17
    assert P.mask_write(0x12, 0xF2, 0x25) == 0x17
    assert P.MaskWriteRegisterRequest(4, 0xF2, 0x25).encode() == bytes.fromhex("16 00 04 00 F2 00 25")
    # FC 23: read 6 from 3, write 3 x 0x00FF from 14
    request = P.ReadWriteMultipleRegistersRequest(3, 6, 14, [0xFF, 0xFF, 0xFF])
    assert request.encode() == bytes.fromhex("17 00 03 00 06 00 0E 00 03 06 00 FF 00 FF 00 FF")
    response = P.decode_pdu(bytes.fromhex("17 0C 00 FE 0A CD 00 01 00 03 00 0D 00 FF"), "response")
    assert response.registers == (0xFE, 0xACD, 1, 3, 0xD, 0xFF)
    # FC 7: the spec's response 07 6D
    assert P.decode_pdu(bytes.fromhex("07 6D"), "response").status == 0x6D
    assert P.ReadExceptionStatusRequest().encode() == b"\x07"


@pytest.mark.parametrize("make, words, error", [
    (lambda: P.MaskWriteRegisterRequest(70000, 0, 0), "outside 0..65535", ValueRangeError),
    (lambda: P.MaskWriteRegisterRequest(0, 0x10000, 0), "outside 0..65535", ValueRangeError),
    (lambda: P.ReadWriteMultipleRegistersRequest(0, 126, 0, [1]), "expected 1 to 125", QuantityError),
    (lambda: P.ReadWriteMultipleRegistersRequest(0, 1, 0, [1] * 122), "expected 1 to 121", QuantityError),
    (lambda: P.ReadWriteMultipleRegistersRequest(0, 1, 65535, [1, 2]), "runs past", mb.ModbusError),
    (lambda: P.ReadExceptionStatusResponse(256), "does not fit", ValueRangeError),
    (lambda: P.ReportServerIdResponse("id"), "must be bytes", ValueRangeError),
    (lambda: P.decode_pdu(bytes.fromhex("17 00 00 00 01 00 00 00 01 03 00 01"), "request"),
     "write byte count 3, expected 2", ByteCountError),
    (lambda: P.decode_pdu(bytes.fromhex("11 02 41 07"), "response"), "run indicator 0x07", ValueRangeError),
])
def test_every_rule_is_enforced_with_a_message(make, words, error):
    with pytest.raises(error, match=words):
        make()


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 0xFFFF), REGS, REGS)
def test_fc22_both_ways_with_pymodbus(address, and_mask, or_mask):
    ours = P.MaskWriteRegisterRequest(address, and_mask, or_mask)
    theirs = pr.MaskWriteRegisterRequest(address=address, and_mask=and_mask, or_mask=or_mask, dev_id=1)
    assert FramerRTU(DecodePDU(is_server=False)).buildFrame(theirs) == mb.RtuFrame(1, ours).encode()
    assert P.decode_pdu(bytes([0x16]) + theirs.encode(), "request") == ours


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 65000), st.integers(1, 125), st.integers(0, 65000),
       st.lists(REGS, min_size=1, max_size=121), st.integers(0, 0xFFFF))
def test_fc23_both_ways_with_pymodbus(read_address, read_count, write_address, values, tid):
    ours = P.ReadWriteMultipleRegistersRequest(read_address, read_count, write_address, values)
    theirs = pr.ReadWriteMultipleRegistersRequest(read_address=read_address, read_count=read_count,
                                                  write_address=write_address, write_registers=values,
                                                  dev_id=1, transaction_id=tid)
    assert FramerSocket(DecodePDU(is_server=False)).buildFrame(theirs) == mb.TcpFrame(tid, 1, ours).encode()
    server = DecodePDU(is_server=True)
    decoded = server.decode(ours.encode())
    assert (decoded.read_address, decoded.read_count, decoded.write_address, list(decoded.write_registers)) \
        == (read_address, read_count, write_address, values)
    response = P.ReadWriteMultipleRegistersResponse(registers=values[:read_count] or [0])
    back = DecodePDU(is_server=False).decode(response.encode())
    assert list(back.registers) == list(response.registers)


def test_fc7_and_fc17_responses_decode_in_pymodbus_and_back():
    client = DecodePDU(is_server=False)
    assert client.decode(P.ReadExceptionStatusResponse(0x6D).encode()).status == 0x6D
    theirs = client.decode(P.ReportServerIdResponse(b"meter 7", False).encode())
    assert theirs.identifier == b"meter 7" and theirs.status is False
    theirs_bytes = po.ReportDeviceIdResponse(identifier=b"PLC", status=True)
    ours = P.decode_pdu(bytes([0x11]) + theirs_bytes.encode(), "response")
    assert ours == P.ReportServerIdResponse(b"PLC", True)


def test_our_server_answers_pymodbus_and_our_master_the_new_functions():
    slave = mb.Slave(unit=1, server_id=b"course meter", exception_status=0b1010)
    slave.bank.holding_registers[4] = 0x12
    with mb.TcpServer(slave) as server:
        client = ModbusTcpClient("127.0.0.1", port=server.address[1])
        assert client.connect()
        try:
            reply = client.mask_write_register(address=4, and_mask=0xF2, or_mask=0x25, device_id=1)
            assert not reply.isError()
            assert slave.bank.holding_registers[4] == 0x17
            reply = client.readwrite_registers(read_address=4, read_count=3, write_address=5, values=[7, 8],
                                               device_id=1)
            assert list(reply.registers) == [0x17, 7, 8]
            assert client.report_device_id(device_id=1).identifier == b"course meter"
            assert client.read_exception_status(device_id=1).status == 0b1010
        finally:
            client.close()
        with mb.tcp_link(*server.address[:2]) as link:
            master = mb.Master(link)
            master.mask_write_register(1, 4, 0x00FF, 0xAB00)
            assert master.read_holding_registers(1, 4, 1) == [P.mask_write(0x17, 0x00FF, 0xAB00)]
            assert master.read_write_multiple_registers(1, 10, 2, 10, [1, 2]) == [1, 2]
            assert master.report_server_id(1).server_id == b"course meter"
            assert master.read_exception_status(1) == 0b1010


def test_fc24_reads_the_queue_and_checks_its_count_both_ways_with_pymodbus():
    slave = mb.Slave(unit=1)
    slave.bank.holding_registers.write(100, [3, 0x1B8, 0x1284, 7])
    slave.bank.holding_registers.write(200, [32])
    link = mb.loopback_serial(slave)
    master = mb.Master(link)
    assert master.read_fifo_queue(1, 100) == [0x1B8, 0x1284, 7]
    with pytest.raises(mb.ModbusExceptionError) as caught:
        master.read_fifo_queue(1, 200)
    assert caught.value.code == 3
    ours = P.ReadFifoQueueResponse((0x1B8, 0x1284))
    assert ours.encode() == bytes.fromhex("18 00 06 00 02 01 B8 12 84")  # the spec's example
    theirs = DecodePDU(is_server=False).decode(ours.encode())
    assert list(theirs.values) == [0x1B8, 0x1284]
    from pymodbus.pdu import file_message as pf

    request = pf.ReadFifoQueueRequest(address=0x4DE, dev_id=1)
    assert P.decode_pdu(bytes([0x18]) + request.encode(), "request") == P.ReadFifoQueueRequest(0x4DE)


def test_the_rtu_splitter_and_explain_know_the_new_lengths():
    frames = [mb.RtuFrame(1, pdu).encode() for pdu in (
        P.MaskWriteRegisterRequest(1, 2, 3), P.ReadWriteMultipleRegistersRequest(0, 2, 0, [5, 6]),
        P.ReadExceptionStatusRequest(), P.ReportServerIdRequest(), P.ReadFifoQueueRequest(5))]
    splitter = mb.framing.RtuSplitter("request")
    assert splitter.feed(b"".join(frames)) == frames
    assert "AND mask" in mb.explain(frames[0]).to_text()


@settings(max_examples=300, deadline=None)
@given(st.sampled_from([0x07, 0x11, 0x16, 0x17, 0x18, 0x2B]), st.binary(max_size=40),
       st.sampled_from(["request", "response"]))
def test_fuzzing_the_new_decoders_lets_only_modbus_errors_out(function, body, role):
    try:
        P.decode_pdu(bytes([function]) + body, role)
    except mb.ModbusError:
        pass


def test_fc43_device_identification_splits_with_more_follows_and_pymodbus_reads_it():
    extended = {0x80 + i: f"x{i}" * 30 for i in range(6)}
    identity = {0: "ACME", 1: "PM-9", 2: "2.1", 4: "Power meter", **extended}
    slave = mb.Slave(unit=1, identity=identity)
    master = mb.Master(mb.loopback_serial(slave))
    assert master.read_device_identification(1) == {0: "ACME", 1: "PM-9", 2: "2.1"}
    everything = master.read_device_identification(1, read_code=3)
    assert everything == identity and master.stats.requests == 1 + 2  # the extended stream came in 2 parts
    assert master.read_device_identification(1, read_code=4, object_id=4) == {4: "Power meter"}
    with pytest.raises(mb.ModbusExceptionError) as caught:
        master.read_device_identification(1, read_code=4, object_id=0x05)
    assert caught.value.code == 2
    with mb.TcpServer(slave) as server:
        client = ModbusTcpClient("127.0.0.1", port=server.address[1])
        assert client.connect()
        try:
            reply = client.read_device_information(read_code=1, object_id=0, device_id=1)
            assert reply.information == {0: b"ACME", 1: b"PM-9", 2: b"2.1"}
        finally:
            client.close()
    from pymodbus.pdu import mei_message as pm

    request = pm.ReadDeviceInformationRequest(read_code=2, object_id=0, dev_id=1)
    ours = P.decode_pdu(bytes([0x2B]) + request.encode(), "request")
    assert ours == P.ReadDeviceIdentificationRequest(2, 0)
    objects = ((0, b"ACME"), (1, b"PM-9"), (2, b"2.1"))
    response = P.ReadDeviceIdentificationResponse(1, 0x81, False, 0, objects)
    theirs = DecodePDU(is_server=False).decode(response.encode())
    assert theirs.information == {0: b"ACME", 1: b"PM-9", 2: b"2.1"}
    assert P.decode_pdu(response.encode(), "response") == response
    frame = mb.RtuFrame(1, response).encode()
    assert mb.framing.RtuSplitter("response").feed(frame) == [frame]
