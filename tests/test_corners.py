"""The spec's corners, attacked with a peer's own bytes: responses that do not fit their request, FC 43's
endless 'more follows', FC 17 as libmodbus sends it, FC 11's counter resets, listen-only mode on every
unit, Modbus/UDP's amplification and a server that listens beyond loopback."""

from __future__ import annotations

import logging
import socket
from collections.abc import Callable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pymodbus.pdu import DecodePDU
from pymodbus.pdu import diag_message as pd
from pymodbus.pdu import other_message as po

import modbus_edu as mb
from modbus_edu import pdu as P
from modbus_edu.crc import crc_bytes
from modbus_edu.errors import ConfigError, PduError, ValueRangeError
from modbus_edu.explain import explain
from modbus_edu.framing import decode_frame
from modbus_edu.links import udp as udp_module
from modbus_edu.master import IDENTIFICATION_TIMEOUTS, MAX_IDENTIFICATION_OBJECTS

LIBMODBUS_FC17 = bytes.fromhex("11 0A B4 FF") + b"LMB3.1.6"
"""libmodbus's answer to Report Server ID (``response_report_slave_id`` in its modbus.c): byte count,
its slave id 0xB4, run indicator 0xFF, then "LMB" and the library's version."""


class Peer(mb.Slave):
    """A device that answers each request with the PDU bytes ``answer(request)`` gives (RTU frames)."""

    def __init__(self, answer: Callable[[P.Pdu], bytes], delay: float = 0.0) -> None:
        super().__init__(unit=1, processing_time=delay)
        self.answer = answer
        self.asked = 0

    def handle(self, frame: bytes, mode: str = "rtu") -> bytes | None:
        request = decode_frame(frame, mode, "request")
        if request.unit != 1:
            return None
        self.asked += 1
        body = bytes([1]) + self.answer(request.pdu)
        return body + crc_bytes(body)


def _refused(answer: Callable[[P.Pdu], bytes], ask: Callable[[mb.Master], object], words: str) -> mb.Master:
    """The master refuses the peer's answer as not fitting, and counts it as a bad response."""
    master = mb.Master(mb.loopback_serial(Peer(answer)), timeout=0.5)
    with pytest.raises(PduError, match=words):
        ask(master)
    assert master.stats.bad_responses == 1 and master.stats.valid_responses == 0
    assert "bad response" in master.log[-1].note
    return master


# -- item 4: every response checked against its request ------------------------------------------------
def test_a_short_fc20_read_is_refused():
    def short(request):  # three registers asked, two sent
        return P.ReadFileRecordResponse(((1, 2),)).encode()

    _refused(short, lambda m: m.read_file_record(1, file=4, record=1, count=3), r"\[2\] registers.*\[3\]")

    def fewer_records(request):
        return P.ReadFileRecordResponse(((1, 2),)).encode()

    two = P.ReadFileRecordRequest(((4, 1, 2), (5, 0, 1)))
    _refused(fewer_records, lambda m: m.execute(1, two), "1 record")


def test_a_wrong_fc21_echo_is_refused():
    def other_value(request):
        return P.WriteFileRecordResponse(((4, 7, (0x06AF, 0x04BF)),)).encode()

    _refused(other_value, lambda m: m.write_file_record(1, 4, 7, [0x06AF, 0x04BE]), "the echo says")


def test_another_fc8_sub_function_or_a_wrong_echo_is_refused():
    def other_counter(request):  # asked for the bus message count, answered the checksum error count
        return P.DiagnosticsResponse(0x0C, b"\x00\x07").encode()

    _refused(other_counter, lambda m: m.diagnostics(1, 0x0B), "sub-function 0x000C, expected 0x000B")

    def wrong_echo(request):
        return P.DiagnosticsResponse(0x00, request.data[:2]).encode()

    _refused(wrong_echo, lambda m: m.diagnostics(1, 0x00, bytes(range(10))), "the echo says 00 01 .2 bytes")

    def long_counter(request):
        return P.DiagnosticsResponse(0x0E, b"\x00\x01\x00\x02").encode()

    _refused(long_counter, lambda m: m.diagnostics(1, 0x0E), "4 data bytes, expected one 16-bit word")


@pytest.mark.parametrize("size", [2, 4, 10, 250])
def test_an_fc8_echo_of_any_even_length_comes_back_on_every_wire(size):
    data = bytes((7 * i + 1) & 0xFF for i in range(size))
    for link in (mb.loopback_serial(mb.Slave(unit=1)), mb.loopback_serial(mb.Slave(unit=1), mode="ascii"),
                 mb.loopback_tcp(mb.Slave(unit=1))):
        assert mb.Master(link).diagnostics(1, 0x00, data) == data
    with mb.TcpServer(mb.Slave(unit=1)) as tcp, mb.TcpServer(mb.Slave(unit=1), framing="rtu") as rtu:
        for server, framing in ((tcp, "tcp"), (rtu, "rtu")):
            with mb.tcp_link(*server.address[:2], framing=framing) as link:
                assert mb.Master(link, timeout=2).diagnostics(1, 0x00, data) == data


def test_a_wrong_fc43_read_code_object_or_mei_type_is_refused():
    def basic(request):
        return P.ReadDeviceIdentificationResponse(1, 0x81, False, 0, ((0, b"ACME"),)).encode()

    _refused(basic, lambda m: m.read_device_identification(1, read_code=2), "ID code 1, expected 2")

    def other_object(request):
        return P.ReadDeviceIdentificationResponse(4, 0x81, False, 0, ((0, b"ACME"),)).encode()

    _refused(other_object, lambda m: m.read_device_identification(1, 4, 5), "0x00, expected .* 0x05")

    def extended_in_basic(request):
        return P.ReadDeviceIdentificationResponse(1, 0x83, False, 0, ((0x80, b"x"),)).encode()

    _refused(extended_in_basic, lambda m: m.read_device_identification(1), "object 0x80 in a basic")

    def other_mei(request):
        return bytes.fromhex("2B 0D 01 81 00 00 00")

    _refused(other_mei, lambda m: m.read_device_identification(1), "MEI type 0x0D")


def test_fc43_more_follows_is_bounded_in_time():
    def endless(request):  # one object per answer, always 'more follows', 0.9 s to answer each
        following = min(request.object_id + 1, 0xFF)
        return P.ReadDeviceIdentificationResponse(3, 0x83, True, following,
                                                  ((request.object_id, b"x"),)).encode()

    peer = Peer(endless, delay=0.9)
    link = mb.loopback_serial(peer)
    master = mb.Master(link, timeout=1.0)
    with pytest.raises(PduError, match="still said 'more follows' after .* responses") as caught:
        master.read_device_identification(1, read_code=3)
    assert isinstance(caught.value, mb.ModbusError)
    # without the bound the device held the master for 255 answers (230 s on this line)
    assert link.clock.now <= (IDENTIFICATION_TIMEOUTS + 1) * master.timeout
    assert peer.asked <= 12


def test_fc43_more_follows_is_bounded_in_objects():
    def crowded(request):  # 30 objects per answer, again and again
        start = request.object_id
        return P.ReadDeviceIdentificationResponse(
            3, 0x83, True, min(start + 1, 0xFF), tuple((0x80 + i, b"") for i in range(30))).encode()

    peer = Peer(crowded)
    with pytest.raises(PduError, match=f"more than the {MAX_IDENTIFICATION_OBJECTS} object ids"):
        mb.Master(mb.loopback_serial(peer)).read_device_identification(1, read_code=3)
    assert peer.asked == MAX_IDENTIFICATION_OBJECTS // 30 + 1


def test_a_long_identification_still_comes_whole():
    identity = {0: "ACME", 1: "PM-9", 2: "2.1", **{0x80 + i: "v" * 40 for i in range(20)}}
    master = mb.Master(mb.loopback_serial(mb.Slave(unit=1, identity=identity)))
    got = master.read_device_identification(1, read_code=3)
    assert got == {key: value for key, value in identity.items()}
    assert master.stats.requests > 1 and master.stats.bad_responses == 0


# -- item 6: FC 17 in the spec's order ---------------------------------------------------------------
def test_libmodbus_fc17_decodes_and_explains():
    report = P.decode_pdu(LIBMODBUS_FC17, "response")
    assert (report.server_id, report.run_indicator, report.additional_data) == (b"\xb4", True, b"LMB3.1.6")
    assert report.encode() == LIBMODBUS_FC17
    master = mb.Master(mb.loopback_serial(Peer(lambda request: LIBMODBUS_FC17)))
    assert master.report_server_id(1) == report
    rows = {row.field: row for row in explain(mb.RtuFrame(1, report).encode(), "rtu", "response").rows}
    assert rows["server ID"].raw == b"\xb4" and rows["run indicator"].raw == b"\xff"
    assert rows["additional data"].raw == b"LMB3.1.6" and "'LMB3.1.6'" in rows["additional data"].meaning


@pytest.mark.parametrize("data", ["11 02 41 07", "11 00", "11 01 FF", "11 03 41 1B 5B"])
def test_an_fc17_without_a_run_indicator_is_shown_unsplit_never_refused(data):
    pdu = bytes.fromhex(data)
    report = P.decode_pdu(pdu, "response")
    assert report.run_indicator is None and report.server_id == pdu[2:] and report.additional_data == b""
    assert report.encode() == pdu
    text = explain(mb.RtuFrame(1, report).encode(), "rtu", "response").to_text()
    assert ("not split" if report.server_id else "no server ID") in text and "\x1b" not in text


def test_the_slave_sends_server_id_run_indicator_then_additional_data():
    slave = mb.Slave(1, mb.DataBank(), server_id=b"\x11", run_indicator=True, additional_data=b"v1.0")
    master = mb.Master(mb.loopback_serial(slave))
    report = master.report_server_id(1)
    assert report.encode() == bytes.fromhex("11 06 11 FF") + b"v1.0"
    assert (report.server_id, report.run_indicator, report.additional_data) == (b"\x11", True, b"v1.0")
    off = mb.Slave(2, server_id=b"\xff", run_indicator=False, additional_data=b"\xff\x00")
    report = mb.Master(mb.loopback_serial(off)).report_server_id(2)
    assert report.encode() == bytes.fromhex("11 04 FF 00 FF 00")


@pytest.mark.parametrize("kwargs, error, words", [
    (dict(server_id=b"AB\xffC"), ValueRangeError, "server ID byte 2 is 0xFF"),
    (dict(server_id=b""), ValueRangeError, "at least one byte"),
    (dict(additional_data="v1"), ValueRangeError, "additional_data must be bytes"),
    (dict(run_indicator=None), ConfigError, "run_indicator must be True"),
    (dict(server_id=b"x" * 200, additional_data=b"y" * 60), ValueRangeError, "at most 251"),
])
def test_a_server_id_the_master_could_not_split_is_refused_at_once(kwargs, error, words):
    with pytest.raises(error, match=words):
        mb.Slave(1, **kwargs)


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 255), st.lists(st.integers(1, 254), max_size=30).map(bytes), st.booleans())
def test_fc17_both_ways_with_pymodbus(first, rest, run):
    server_id = bytes([first]) + rest
    ours = P.ReportServerIdResponse(server_id, run)
    theirs = po.ReportDeviceIdResponse(identifier=server_id, status=run)
    assert bytes([0x11]) + theirs.encode() == ours.encode()
    assert P.decode_pdu(bytes([0x11]) + theirs.encode(), "response") == ours
    back = DecodePDU(is_server=False).decode(ours.encode())
    assert back.identifier == server_id and back.status is run


@settings(max_examples=100, deadline=None)
@given(st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=60))
def test_fc8_return_query_data_of_any_length_both_ways_with_pymodbus(words):
    data = b"".join(word.to_bytes(2, "big") for word in words)
    theirs = pd.ReturnQueryDataRequest(message=data)
    assert bytes([0x08]) + theirs.encode() == P.DiagnosticsRequest(0x00, data).encode()
    assert P.decode_pdu(bytes([0x08]) + theirs.encode(), "request") == P.DiagnosticsRequest(0x00, data)
    back = DecodePDU(is_server=False).decode(P.DiagnosticsResponse(0x00, data).encode())
    assert back.sub_function_code == 0 and back.message == data


def test_fc11_event_counter_is_reset_by_restart_and_by_clear_counters():
    slave = mb.Slave(unit=1)
    master = mb.Master(mb.loopback_serial(slave))
    for _ in range(3):
        master.read_holding_registers(1, 0, 1)
    assert master.get_comm_event_counter(1) == 3
    master.diagnostics(1, 0x0A)  # clear counters and diagnostic register
    assert master.get_comm_event_counter(1) == 0
    master.write_single_register(1, 0, 5)
    assert master.get_comm_event_counter(1) == 1
    master.diagnostics(1, 0x01)  # restart communications
    assert master.get_comm_event_counter(1) == 0
    master.read_holding_registers(1, 0, 1)
    assert master.get_comm_event_log(1).event_count == 1


ZERO_QUANTITY = bytes.fromhex("00 09 00 00 00 06 01 03 00 00 00 00")
"""FC 3 for 0 registers, transaction 9: a slave answers exception 03 (the PDU does not decode)."""


def _silent(master: mb.Master, unit: int) -> bool:
    try:
        master.read_holding_registers(unit, 0, 1)
    except mb.ModbusTimeoutError:
        return True
    return False


@pytest.mark.parametrize("wire", ["loopback", "server"])
def test_listen_only_silences_every_unit_the_slave_answers_on_tcp(wire):
    slave = mb.Slave(unit=1)
    server = mb.TcpServer(slave) if wire == "server" else None
    link = mb.loopback_tcp(slave) if server is None else mb.tcp_link(*server.start().address[:2])
    try:
        master = mb.Master(link, timeout=0.2)
        link.send(ZERO_QUANTITY)
        assert link.receive(1.0) == bytes.fromhex("00 09 00 00 00 03 01 83 03")  # exception 03, normally
        master.diagnostics(0xFF, 0x04)  # force listen-only mode, sent to the device itself
        assert all(_silent(master, unit) for unit in (1, 0, 0xFF))
        assert slave.listen_only and slave.counters.requests == 5 and slave.counters.responses == 1
        link.send(ZERO_QUANTITY)  # not even an exception response
        assert link.receive(0.2) is None
        # restart communications, through unit 0: it ends listen-only mode, unanswered (the spec)
        master.execute_no_answer(0x00, P.DiagnosticsRequest(0x01))
        assert not any(_silent(master, unit) for unit in (1, 0, 0xFF))
        assert not slave.listen_only
    finally:
        link.close()
        if server is not None:
            server.close()


def test_listen_only_takes_no_action_on_a_broadcast_and_any_unit_slave_stays_silent():
    slave = mb.Slave(unit=None)
    link = mb.loopback_serial(slave)
    master = mb.Master(link, timeout=0.2)
    master.diagnostics(5, 0x04)
    master.write_single_register(0, 3, 99)  # a broadcast: heard, not carried out
    assert slave.bank.holding_registers[3] == 0
    assert _silent(master, 7) and _silent(master, 5)
    master.execute_no_answer(7, P.DiagnosticsRequest(0x01))  # restart communications: unanswered
    assert not slave.listen_only and not _silent(master, 5)
    master.write_single_register(0, 3, 99)
    assert slave.bank.holding_registers[3] == 99


# -- item 7: Modbus/UDP -------------------------------------------------------------------------------
def test_udp_amplification_is_what_the_docstring_says():
    with mb.UdpServer(mb.Slave(unit=1)) as server, socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        sock.settimeout(2)
        request = mb.TcpFrame(1, 1, P.ReadHoldingRegistersRequest(0, 125)).encode()
        sock.sendto(request, server.address)
        response, _ = sock.recvfrom(2048)
    ratio = len(response) / len(request)
    assert (len(request), len(response)) == (12, 259)
    with_headers = (len(response) + 28) / (len(request) + 28)  # IPv4 (20 bytes) and UDP (8) headers
    assert f"{ratio:.1f} x" in mb.UdpServer.__doc__ and f"{with_headers:.1f} x" in mb.UdpServer.__doc__


def test_a_udp_server_beyond_loopback_warns_and_on_loopback_does_not(caplog, monkeypatch):
    with caplog.at_level(logging.WARNING, logger="modbus_edu.udp"):
        mb.UdpServer(mb.Slave(unit=1)).close()
    assert not caplog.records
    monkeypatch.setattr(udp_module, "is_loopback_host", lambda host: False)
    with caplog.at_level(logging.WARNING, logger="modbus_edu.udp"):
        mb.UdpServer(mb.Slave(unit=1)).close()  # really 127.0.0.1: the check is what is tested
    assert len(caplog.records) == 1
    message = caplog.records[0].getMessage()
    assert "no authentication" in message and "21.6 times" in message


def test_explain_shows_a_device_identification_object_escaped():
    pdu = P.ReadDeviceIdentificationResponse(1, 0x81, False, 0, ((0, b"ACME\x1b[2J\n"), (1, b"PM-9")))
    rows = explain(mb.RtuFrame(1, pdu).encode(), "rtu", "response").rows
    assert [row.value for row in rows if row.field in ("VendorName", "ProductCode")] == ["ACME\\x1b[2J\\n",
                                                                                        "PM-9"]
