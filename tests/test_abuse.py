"""One misbehaving peer costs nobody else anything: the Master's deadline and the TcpServer's defences.

Each test here failed before the defence it checks existed.  Sizes are small so the tests take seconds;
bench/ has the full-size figures.
"""

from __future__ import annotations

import errno
import logging
import socket
import threading
import time

import pytest
from conftest_io import HOST, is_closed_by_peer, raw_client, recv_frame

import modbus_edu as mb
from modbus_edu.links.tcp import TcpServer


def _request(tid: int, unit: int = 1) -> bytes:
    return mb.TcpFrame(transaction_id=tid, unit=unit,
                       pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()


class StreamingPeer:
    """A TCP 'server' that answers every connection with an endless stream of foreign responses."""

    def __init__(self) -> None:
        self.listener = socket.create_server((HOST, 0))
        self.port = self.listener.getsockname()[1]
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        conn, _ = self.listener.accept()
        foreign = mb.TcpFrame(transaction_id=0xBEEF, unit=1,
                              pdu=mb.ReadHoldingRegistersResponse(registers=[1])).encode() * 200
        try:
            while not self.stop.is_set():
                conn.sendall(foreign)
        except OSError:
            pass
        finally:
            conn.close()

    def close(self) -> None:
        self.stop.set()
        self.listener.close()


def test_a_peer_that_never_stops_sending_cannot_hold_the_master_past_its_timeout():
    peer = StreamingPeer()
    try:
        with mb.tcp_link(HOST, peer.port) as link:
            master = mb.Master(link, timeout=0.3)
            start = time.monotonic()
            with pytest.raises(mb.TransactionMismatchError) as caught:
                master.read_holding_registers(unit=1, address=0, count=1)
            elapsed = time.monotonic() - start
    finally:
        peer.close()
    assert elapsed < 1.5, f"the master waited {elapsed:.2f} s on a 0.3 s timeout"
    assert len(str(caught.value)) < 600 and "more" in str(caught.value)
    assert master.stats.mismatches > 3 and len(master.log) <= mb.master.MAX_LOG


def test_the_master_log_and_latencies_are_bounded():
    link = mb.loopback_serial(mb.Slave(unit=1), baudrate=115200)
    master = mb.Master(link)
    master.log = mb.TrafficLog(maxlen=50)
    for _ in range(100):
        master.read_holding_registers(unit=1, address=0, count=1)
    assert len(master.log) == 50
    assert master.stats.latencies.maxlen == mb.master.MAX_LATENCIES


@pytest.fixture
def server():
    with TcpServer(mb.Slave(unit=1), request_timeout=0.4, max_connections=4) as running:
        yield running


def test_a_request_trickled_byte_by_byte_is_closed_at_its_deadline_and_others_are_served(server):
    port = server.address[1]
    with raw_client(port) as slow, raw_client(port) as good:
        frame = _request(1)
        start = time.monotonic()
        closed = False
        for byte in frame[:-1]:  # never completes, but is never silent for long either
            try:
                slow.sendall(bytes([byte]))
            except OSError:
                closed = True
                break
            good.sendall(_request(7))
            assert recv_frame(good)[:2] == b"\x00\x07"
            time.sleep(0.1)
        closed = closed or is_closed_by_peer(slow)
        assert closed and time.monotonic() - start < 2.0
    assert server.counters.slow_closed == 1


def test_idle_clients_at_the_limit_do_not_lock_out_a_new_one(server):
    port = server.address[1]
    idle = [socket.create_connection((HOST, port), timeout=2) for _ in range(6)]  # more than the limit
    try:
        with raw_client(port) as newcomer:
            newcomer.sendall(_request(9))
            assert recv_frame(newcomer)[:2] == b"\x00\x09"
        assert server.counters.evicted >= 3
    finally:
        for sock in idle:
            sock.close()


def _drain(sock: socket.socket) -> None:
    try:
        while sock.recv(1 << 16):
            pass
    except OSError:
        pass


def test_a_pipelining_client_does_not_delay_another_client():
    handled: list[int] = []
    slaves = [mb.Slave(unit=unit, on_read=lambda slave, *_: handled.append(slave.unit)) for unit in (1, 2)]
    with TcpServer(slaves) as server:
        port = server.address[1]
        with raw_client(port) as greedy, raw_client(port) as polite:
            burst = b"".join(_request(tid & 0xFFFF, unit=1) for tid in range(20_000))
            reader = threading.Thread(target=_drain, args=(greedy,), daemon=True)
            reader.start()
            greedy.sendall(burst[:120_000])
            polite.sendall(_request(1, unit=2))
            assert recv_frame(polite)[6] == 2
            position = handled.index(2)
            greedy.sendall(burst[120_000:])
    assert position < 5000, f"the polite client's request was handled after {position} of the greedy one's"


def test_accept_failures_pause_accepting_and_warn_once(caplog):
    class Listener:
        calls = 0

        def accept(self):
            Listener.calls += 1
            raise OSError(errno.EMFILE, "Too many open files")

    class Selector:
        def __init__(self):
            self.registered = True

        def unregister(self, _):
            self.registered = False

        def register(self, *_):
            self.registered = True

    server = TcpServer(mb.Slave(unit=1))
    server._listener, server._selector = Listener(), Selector()
    with caplog.at_level(logging.WARNING, logger="modbus_edu.tcp"):
        for _ in range(50):
            server._accept()
            assert not server._selector.registered and server._accept_paused_until > time.monotonic()
            server._accept_paused_until = time.monotonic() - 1  # the pause is over
            server._expire()
            assert server._selector.registered
    assert Listener.calls == 50
    assert len([r for r in caplog.records if "accept failed" in r.getMessage()]) == 1
    server._listener = server._selector = None


# --- only our errors come out --------------------------------------------------------------------------
HUGE = 10**5000  # Python refuses to print it (4300 digits at most) and to make a float of it


def _pdu():
    return mb.ReadHoldingRegistersRequest(address=0, count=1)


HOSTILE_CALLS = {
    "request address": lambda: mb.ReadHoldingRegistersRequest(address=HUGE, count=1),
    "request count": lambda: mb.ReadHoldingRegistersRequest(address=0, count=HUGE),
    "register value": lambda: mb.WriteSingleRegisterRequest(address=0, value=HUGE),
    "register values": lambda: mb.WriteMultipleRegistersRequest(address=0, values=[HUGE]),
    "response registers": lambda: mb.ReadHoldingRegistersResponse(registers=[HUGE]),
    "exception function": lambda: mb.ExceptionResponse(function=HUGE, code=1),
    "exception code": lambda: mb.ExceptionResponse(function=3, code=HUGE),
    "tcp transaction id": lambda: mb.TcpFrame(transaction_id=HUGE, unit=1, pdu=_pdu()),
    "tcp unit": lambda: mb.TcpFrame(transaction_id=1, unit=HUGE, pdu=_pdu()),
    "rtu unit": lambda: mb.RtuFrame(unit=HUGE, pdu=_pdu()),
    "slave unit": lambda: mb.Slave(unit=HUGE),
    "slave processing time": lambda: mb.Slave(unit=1, processing_time=HUGE),
    "server port": lambda: TcpServer(mb.Slave(), port=HUGE),
    "server idle timeout": lambda: TcpServer(mb.Slave(), idle_timeout=HUGE),
    "server request timeout": lambda: TcpServer(mb.Slave(), request_timeout=HUGE),
    "encode uint16": lambda: mb.encode_value(HUGE, "uint16"),
    "encode float32": lambda: mb.encode_value(HUGE, "float32"),
    "format registers": lambda: mb.format_registers([HUGE], "hex"),
    "scale to infinity": lambda: mb.values.scale(10**400, 0.1),
    "unscale past the decimal context": lambda: mb.values.unscale(1e27, 10),
    "crc16 of an int": lambda: mb.crc16(5),
    "lrc of an int": lambda: mb.lrc(5),
    "crc16 of a str": lambda: mb.crc16("01 03"),
    "bank value": lambda: mb.DataBank().holding_registers.__setitem__(0, HUGE),
    "bank address": lambda: mb.DataBank().holding_registers[HUGE],
    "reference number": lambda: mb.parse_reference("4" + "1" * 5000),
    "format reference": lambda: mb.format_reference("coils", HUGE),
    "master timeout": lambda: mb.Master(mb.loopback_serial(mb.Slave()), timeout=HUGE),
    "master transaction id": lambda: mb.Master(mb.loopback_serial(mb.Slave()), transaction_id=HUGE),
    "loopback baud rate": lambda: mb.loopback_serial(mb.Slave(), baudrate=HUGE),
    "read address": lambda: mb.Master(mb.loopback_serial(mb.Slave())).read_holding_registers(1, HUGE, 1),
    "read unit": lambda: mb.Master(mb.loopback_serial(mb.Slave())).read_holding_registers(HUGE, 0, 1),
    "tcp_link port": lambda: mb.tcp_link(HOST, HUGE),
    "tcp_link timeout": lambda: mb.tcp_link(HOST, 502, timeout=HUGE),
}


@pytest.mark.parametrize("name", sorted(HOSTILE_CALLS))
def test_huge_and_wrong_values_give_a_modbus_error_with_a_short_message(name):
    with pytest.raises(mb.ModbusError) as caught:
        HOSTILE_CALLS[name]()
    assert len(str(caught.value)) < 400


def test_a_setting_the_operating_system_refuses_is_a_link_error_naming_it(monkeypatch):
    termios = pytest.importorskip("termios")
    import serial

    def refuse(*args, **kwargs):
        raise termios.error(22, "Invalid argument")

    monkeypatch.setattr(serial, "serial_for_url", refuse)
    with pytest.raises(mb.LinkError, match="refused the settings 9600 baud 7N1"):
        mb.serial_link("/dev/ttyS99", mode="ascii")


# --- linear-time splitters with bounded look-behind ------------------------------------------------------
def test_a_long_run_of_colons_is_cut_in_linear_time():
    splitter = mb.framing.AsciiSplitter()
    frame = mb.AsciiFrame(unit=5, pdu=mb.WriteSingleRegisterRequest(address=0x1001, value=0x0200)).encode()
    assert splitter.feed(b":" * 400_000 + frame) == [frame]  # quadratic before: minutes for this
    assert splitter.discarded == 400_000


@pytest.mark.parametrize("role", ["request", "response"])
def test_rtu_junk_fed_byte_by_byte_keeps_at_most_one_frame_of_look_behind(role):
    import random

    splitter = mb.framing.RtuSplitter(role)
    junk = random.Random(5).randbytes(30_000)
    for byte in junk:
        splitter.feed(bytes([byte]))
        assert len(splitter.pending) <= 256
    good = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
    if role == "request":
        assert splitter.feed(good)[-1:] == [good]


def test_the_crc_explorer_refuses_more_bytes_than_it_can_step_through():
    from modbus_edu.widgets import CrcExplorer
    from modbus_edu.widgets.crcexplorer import MAX_BITWISE_BYTES

    explorer = CrcExplorer("00 " * (MAX_BITWISE_BYTES + 1))
    assert explorer.steps == [] and "too many to follow bit by bit" in explorer.message.text
    explorer = CrcExplorer("00 " * (MAX_BITWISE_BYTES + 1), method="table")
    assert len(explorer.steps) > MAX_BITWISE_BYTES


# --- the TestTool's configuration: report, change nothing, never raise ---------------------------------
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

JSON_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=12),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=12)


@settings(max_examples=60, deadline=None)
@given(st.dictionaries(st.sampled_from(["port", "unit", "timeout", "interval", "baudrate", "parity", "role",
                                        "display", "seed", "length", "continuous", "name", "x"]),
                       JSON_VALUES, max_size=4))
def test_any_json_configuration_is_applied_whole_or_refused_with_nothing_changed(config):
    from modbus_edu.widgets import TestTool

    tool = TestTool("rtu_master")
    before = tool.config()
    if not tool.apply_config(config):
        assert tool.config() == before and tool.message.kind == "error"


@pytest.mark.parametrize("config, words", [
    ({"port": 10**100}, "port must be 0 to 65535"),
    ({"unit": -1}, "unit must be 0 to 255"),
    ({"interval": float("nan")}, "interval is a number"),
    ({"timeout": 10**5000}, "timeout must be"),
    ({"baudrate": 12345}, "baudrate must be one of"),
    ({"continuous": "yes"}, "continuous is true or false"),
])
def test_out_of_range_settings_are_refused_not_clamped(config, words):
    from modbus_edu.widgets import TestTool

    tool = TestTool("tcp_client")
    before = tool.config()
    assert tool.apply_config(config) is False
    assert words in tool.message.text and tool.config() == before


def test_from_config_and_load_config_report_unreadable_files(tmp_path):
    from modbus_edu.widgets import TestTool

    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    broken = tmp_path / "broken.json"
    broken.write_text("{not json")
    for path in (deep, broken, tmp_path / "missing.json"):
        with pytest.raises(mb.ConfigError):
            TestTool.from_config(path)
        tool = TestTool("rtu_master")
        assert tool.load_config(path) is False and tool.message.kind == "error"
    with pytest.raises(mb.ConfigError, match="unknown role"):
        TestTool.from_config({"role": ["rtu_master"]})
    with pytest.raises(mb.ConfigError, match="port must be"):
        TestTool.from_config({"role": "tcp_client", "port": 70000})


def test_panels_report_huge_numbers_beside_the_field():
    from modbus_edu.widgets import FrameBuilder, TestTool

    builder = FrameBuilder(unit=HUGE)
    assert builder.frame == b"" and "unit" in builder.message.text
    tool = TestTool("rtu_slave")
    tool._cells[0].value = "9" * 5000
    assert tool.grid_message.kind == "error" and "far too large" in tool.grid_message.text
