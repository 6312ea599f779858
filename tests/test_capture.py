"""Captures: Wireshark's own dissector (tshark) judges the pcap files we write, and we read its captures.

tshark is Debian's (``.ci/run`` installs it).  Without it the tests that need it are skipped with the
reason, unless the environment variable ``CI`` is set: then a missing tshark FAILS them.
"""

from __future__ import annotations

import os
import shutil
import signal
import struct
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import modbus_edu as mb
from modbus_edu.capture import LINKTYPE_ASCII, LINKTYPE_RTU, TSHARK_ASCII, TSHARK_RTU

TSHARK = shutil.which("tshark")
HERE_FUNCTIONS = [1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 15, 16, 17, 20, 21, 22, 23, 24, 43]


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


@pytest.fixture(scope="module")
def tshark() -> str:
    """The path of tshark, or skip (locally) / fail (in CI) with the reason."""
    if TSHARK is None:
        reason = "tshark is not installed (apt-get install tshark)"
        if _in_ci():
            pytest.fail(reason + " -- and CI is set, so this is a failure, not a skip")
        pytest.skip(reason)
    return TSHARK


def run_tshark(*args: str) -> str:
    result = subprocess.run([TSHARK, *args], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    return result.stdout


def fields(path: Path, names: list[str], *options: str, display: str = "") -> list[dict[str, list[str]]]:
    """tshark's value(s) of each field, one dict per packet shown."""
    args = [*options, "-r", str(path), "-T", "fields", "-E", "separator=\t", "-E", "occurrence=a",
            "-E", "aggregator=|"]
    if display:
        args += ["-Y", display]
    for name in names:
        args += ["-e", name]
    rows = []
    for line in run_tshark(*args).splitlines():
        values = line.split("\t")
        rows.append({n: [v for v in value.split("|") if v] for n, value in zip(names, values)})
    return rows


# --- traffic: every function the library speaks, through a real exchange ------------------------------
def course_slave() -> mb.Slave:
    slave = mb.Slave(unit=1, identity={0: "ACME", 1: "PM-9", 2: "2.1"}, server_id=b"meter")
    slave.bank.holding_registers.write(0, [11, 22, 33, 0x12])
    slave.bank.holding_registers.write(100, [2, 0x1B8, 0x1284])
    slave.bank.holding_registers.write(200, [32])     # a queue of 32: more than FC 24 may return
    slave.bank.input_registers.write(0, [7, 65535])
    slave.bank.coils.write(0, [True, False, True, True, False, False, True, False, True, True])
    slave.bank.discrete_inputs.write(0, [False, True] * 5)
    slave.bank.files[4] = list(range(100, 120))
    return slave


def every_function(master: mb.Master, unit: int = 1) -> None:
    """One request of each function code the library speaks, and one that gets an exception response."""
    master.read_coils(unit, 0, 10)
    master.read_discrete_inputs(unit, 0, 9)
    master.read_holding_registers(unit, 0, 3)
    master.read_input_registers(unit, 0, 2)
    master.write_single_coil(unit, 3, True)
    master.write_single_register(unit, 2, 0x1234)
    master.read_exception_status(unit)
    master.diagnostics(unit, 0x00, bytes.fromhex("A5 37"))
    master.get_comm_event_counter(unit)
    master.get_comm_event_log(unit)
    master.write_multiple_coils(unit, 10, [True, False, True])
    master.write_multiple_registers(unit, 5, [7, 8, 9])
    master.report_server_id(unit)
    master.read_file_record(unit, 4, 1, 2)
    master.write_file_record(unit, 4, 7, [0x06AF, 0x04BE])
    master.mask_write_register(unit, 3, 0xF2, 0x25)
    master.read_write_multiple_registers(unit, 3, 4, 14, [0xFF, 0xFE])
    master.read_fifo_queue(unit, 100)
    master.read_device_identification(unit)
    with pytest.raises(mb.ModbusExceptionError):
        master.read_fifo_queue(unit, 200)


@pytest.fixture(scope="module")
def tcp_log() -> mb.TrafficLog:
    """A master's log of every function over a real loopback socket to our TcpServer."""
    with mb.TcpServer(course_slave()) as server, mb.tcp_link(*server.address[:2]) as link:
        master = mb.Master(link)
        every_function(master)
    return master.log


@pytest.fixture(scope="module")
def rtu_monitor() -> mb.TrafficLog:
    """The wire monitor of the same exchange on a 9600-baud RTU line (virtual time)."""
    link = mb.loopback_serial(course_slave(), baudrate=9600)
    every_function(mb.Master(link))
    return link.monitor


# --- what explain says, in tshark's terms ------------------------------------------------------------------
def ours(entry: mb.Traffic) -> dict[str, list[str]]:
    """The fields tshark reports, worked out from explain's dissection of the frame."""
    dissection = mb.explain(entry.data, entry.mode, entry.role)
    assert dissection.ok, dissection.error
    frame, pdu = dissection.frame, dissection.pdu if dissection.pdu is not None else dissection.frame.pdu
    out: dict[str, list[str]] = {"unit_id": [str(frame.unit)]}
    if entry.mode == "tcp":
        out["trans_id"] = [str(frame.transaction_id)]
    if isinstance(pdu, mb.ExceptionResponse):
        out["func_code"] = [str(int(pdu.function))]
        out["exception_code"] = [str(int(pdu.code))]
        return out
    function = pdu.encode()[0]
    out["func_code"] = [str(function)]
    if hasattr(pdu, "address"):
        out["address"] = [str(pdu.address)]
    if hasattr(pdu, "read_address"):
        out["address"] = [str(pdu.read_address), str(pdu.write_address)]
    registers = None
    if hasattr(pdu, "registers"):
        registers = pdu.registers
    elif function in (16, 23, 24) and hasattr(pdu, "values"):
        registers = pdu.values
    elif function == 6:
        registers = [pdu.value]
    if registers is not None:
        out["registers"] = [str(v) for v in registers]
    return out


def theirs(row: dict[str, list[str]]) -> dict[str, list[str]]:
    """tshark's fields of one frame, named as :func:`ours` names them."""
    out = {"unit_id": row.get("mbtcp.unit_id") or row.get("mbrtu.unit_id"),
           "func_code": row["modbus.func_code"]}
    if row.get("mbtcp.trans_id"):
        out["trans_id"] = row["mbtcp.trans_id"]
    if row.get("modbus.exception_code"):
        out["exception_code"] = row["modbus.exception_code"]
        return out
    function = int(row["modbus.func_code"][0])
    address = row.get("modbus.reference_num") or (
        row.get("modbus.read_reference_num", []) + row.get("modbus.write_reference_num", []))
    if address:
        out["address"] = address
    if row.get("modbus.regval_uint16"):
        out["registers"] = row["modbus.regval_uint16"]
    elif function in (6, 23, 24) and row.get("modbus.data"):
        data = bytes.fromhex(row["modbus.data"][0])
        out["registers"] = [str(v) for v in struct.unpack(f">{len(data) // 2}H", data)]
    return out


MODBUS_FIELDS = ["frame.number", "mbtcp.trans_id", "mbtcp.unit_id", "mbrtu.unit_id", "modbus.func_code",
                 "modbus.exception_code", "modbus.reference_num", "modbus.read_reference_num",
                 "modbus.write_reference_num", "modbus.regval_uint16", "modbus.data", "modbus.request_frame"]


def compare(entry: mb.Traffic, row: dict[str, list[str]]) -> None:
    mine, wireshark = ours(entry), theirs(row)
    # every field explain gives, tshark gives too, with the same value; except where tshark reports a
    # response's address from its request (FC 5, 6, 22 echo theirs; FC 15/16 responses carry it)
    for name, value in mine.items():
        assert wireshark.get(name) == value, (name, entry, row)
    for name in wireshark:
        if name not in mine:
            assert name == "address" and entry.role == "response", (name, entry, row)


# --- Modbus/TCP --------------------------------------------------------------------------------------------
def test_tshark_dissects_every_function_of_a_tcp_capture_as_explain_does(tshark, tcp_log, tmp_path):
    path = mb.write_pcap(tcp_log, tmp_path / "every_function.pcap")
    assert {entry.function & 0x7F for entry in tcp_log} == set(HERE_FUNCTIONS)
    assert any(entry.function & 0x80 for entry in tcp_log)            # and an exception response
    rows = fields(path, MODBUS_FIELDS, display="mbtcp")
    assert len(rows) == len(tcp_log) == 40
    for entry, row in zip(tcp_log, rows):
        compare(entry, row)
    # responses are matched to their requests: Wireshark followed the one TCP stream (it links no
    # exception response, the last, to its request)
    assert [r["modbus.request_frame"] for r in rows[1:-1:2]] == [[r["frame.number"][0]] for r in rows[:-2:2]]
    assert run_tshark("-r", str(path), "-Y", "_ws.malformed || _ws.expert.severity >= warning") == ""
    # the handshake, checksums and sequence numbers are those of a healthy connection
    flags = fields(path, ["tcp.flags.str", "tcp.checksum.status", "ip.checksum.status"],
                   "-o", "tcp.check_checksum:TRUE", "-o", "ip.check_checksum:TRUE")
    assert [f["tcp.flags.str"][0].replace("·", "") for f in flags[:3]] == ["S", "AS", "A"]
    assert {f["tcp.checksum.status"][0] for f in flags} == {"1"}
    assert {f["ip.checksum.status"][0] for f in flags} == {"1"}
    analysis = run_tshark("-r", str(path), "-Y", "tcp.analysis.flags && !tcp.analysis.window_update")
    assert analysis == ""
    assert fields(path, ["tcp.stream"], display="mbtcp") == [{"tcp.stream": ["0"]}] * 40


def test_reading_back_what_we_wrote_gives_the_logs_frames(tcp_log, rtu_monitor, tmp_path):
    for log in (tcp_log, rtu_monitor):
        back = mb.read_pcap(mb.write_pcap(log, tmp_path / "x.pcap"))
        assert [(e.data, e.mode, e.role, e.direction) for e in back] == \
               [(e.data, e.mode, e.guessed_role, e.direction) for e in log]
        assert [round(e.time * 1e9) for e in back] == [round(e.time * 1e9) for e in log]
        assert all(back.explain(i).ok for i in range(len(back)))
    back = mb.read_pcap(tmp_path / "x.pcap")
    assert back[0].source == "master" and back[1].dest == "master" and back[0].dest == "unit 1"


def test_a_slaves_log_is_written_from_the_clients_side(tmp_path):
    slave = course_slave()
    master = mb.Master(mb.loopback_tcp(slave))
    master.read_holding_registers(1, 0, 2)
    back = mb.read_pcap(mb.write_pcap(slave.log, tmp_path / "slave.pcap"))
    # the slave received the request ("rx" in its log): on the wire it goes from the client to port 502
    assert [(e.role, e.source, e.dest) for e in back] == [
        ("request", "127.0.0.1:49152", "127.0.0.2:502"), ("response", "127.0.0.2:502", "127.0.0.1:49152")]
    assert [e.data for e in back] == [e.data for e in slave.log]


def test_importing_the_library_leaves_scapy_unloaded():
    code = "import sys, modbus_edu; print('scapy' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                            env={**os.environ, "PYTHONPATH": str(Path(mb.__file__).parent.parent)})
    assert result.stdout.strip() == "False", result.stderr


# --- serial ---------------------------------------------------------------------------------------------
def test_tshark_dissects_an_rtu_capture_with_the_documented_setting(tshark, rtu_monitor, tmp_path):
    path = mb.write_pcap(rtu_monitor, tmp_path / "rtu.pcap")
    assert fields(path, ["frame.encap_type"])[0]["frame.encap_type"] == ["45"]   # wiretap's USER0 (DLT 147)
    assert fields(path, ["frame.protocols"])[0]["frame.protocols"] == ["user_dlt:data"]  # without the setting
    options = ["-o", TSHARK_RTU, "-o", "mbrtu.crc_verification:TRUE"]
    rows = fields(path, [*MODBUS_FIELDS, "mbrtu.crc16.status", "frame.time_relative", "_ws.col.Info"],
                  *options)
    assert len(rows) == len(rtu_monitor)
    dissected = 0
    for entry, row in zip(rtu_monitor, rows):
        # the timestamps are the wire's: tshark shows the same times, to the nanosecond
        assert round(float(row["frame.time_relative"][0]) * 1e9) == round(entry.time * 1e9)
        if len(entry.data) < 5:
            # Wireshark's mbrtu takes no frame shorter than 5 bytes (an exception response is the shortest
            # it expects): the 4-byte requests of FC 7, 11, 12 and 17 stay undissected bytes
            assert entry.role == "request" and entry.function in (7, 11, 12, 17)
            assert not row["modbus.func_code"]
            continue
        dissected += 1
        assert row["mbrtu.crc16.status"] == ["1"]                               # CRC good
        info = row["_ws.col.Info"][0]
        if "Unable to classify" in info:
            # without a direction on the line mbrtu guesses request/response from lengths, and only for
            # FC 1-4, 15, 16 and exception responses; then it names the unit and the function only
            assert row["mbrtu.unit_id"] == [str(entry.unit)]
            assert row["modbus.func_code"] == [str(entry.function)]
            continue
        assert info.lstrip().startswith("Query" if entry.role == "request" else "Response"), info
        compare(entry, row)
    assert dissected >= 20
    assert run_tshark(*options, "-r", str(path), "-Y", "_ws.malformed || _ws.expert.severity >= warning") \
        == ""


def test_the_tshark_helper_adds_the_serial_setting_and_says_when_tshark_is_missing(tshark, rtu_monitor,
                                                                                   tmp_path, monkeypatch):
    path = mb.write_pcap(rtu_monitor, tmp_path / "rtu.pcap")
    shown = mb.capture.tshark(path, "-Y", "modbus.func_code == 3")
    assert shown.count("Modbus RTU") == 2 and "Read Holding Registers" in shown
    with pytest.raises(mb.CaptureError, match="tshark could not read"):
        mb.capture.tshark(path, "-Y", "no such field ((")
    monkeypatch.setenv("PATH", str(tmp_path))
    assert mb.capture.tshark(path) is None


def test_the_rtu_silences_show_in_the_capture(rtu_monitor, tmp_path):
    back = mb.read_pcap(mb.write_pcap(rtu_monitor, tmp_path / "rtu.pcap"))
    character = 10 / 9600
    request, response = back[0], back[1]
    # the response starts 3.5 characters after the request's last character
    gap = response.time - (request.time + len(request.data) * character)
    assert gap == pytest.approx(3.5 * character, abs=2e-9)


def test_an_ascii_capture_is_text_lines_in_tshark(tshark, tmp_path):
    link = mb.loopback_serial(course_slave(), mode="ascii")
    mb.Master(link).read_holding_registers(1, 0, 2)
    path = mb.write_pcap(link.monitor, tmp_path / "ascii.pcap")
    rows = fields(path, ["frame.encap_type", "frame.protocols"], "-o", TSHARK_ASCII)
    assert [r["frame.protocols"] for r in rows] == [["user_dlt:data-text-lines"]] * 2
    shown = run_tshark("-o", TSHARK_ASCII, "-r", str(path), "-V")
    for entry in link.monitor:
        assert entry.data.decode().replace("\r\n", "\\r\\n") in shown
    back = mb.read_pcap(path)
    assert [(e.mode, e.role, e.data) for e in back] == [("ascii", e.role, e.data) for e in link.monitor]


# --- tshark's own capture of our server ------------------------------------------------------------------
def test_read_pcap_reads_what_tshark_captured_of_our_server_on_lo(tshark, tmp_path):
    if os.geteuid() != 0 and not _in_ci():
        pytest.skip("capturing on lo needs root (or the wireshark group)")
    with mb.TcpServer(course_slave()) as server:
        port = server.address[1]
        path = tmp_path / "lo.pcapng"
        # bounded: tshark stops by itself after 60 s; we stop it as soon as the exchange is over
        capture = subprocess.Popen([TSHARK, "-i", "lo", "-f", f"tcp port {port}", "-w", str(path),
                                    "-a", "duration:60"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                   text=True)
        try:
            deadline = time.monotonic() + 30
            started = ""
            while "Capturing on" not in started and time.monotonic() < deadline:
                line = capture.stderr.readline()
                if not line:
                    break
                started += line
            assert "Capturing on" in started, started
            time.sleep(0.5)
            with mb.tcp_link("127.0.0.1", port) as link:
                master = mb.Master(link)
                every_function(master)
            time.sleep(0.5)
        finally:
            capture.send_signal(signal.SIGINT)
            try:
                capture.wait(timeout=20)
            except subprocess.TimeoutExpired:
                capture.kill()
                capture.wait(timeout=5)
    assert path.read_bytes()[:4] == b"\x0a\x0d\x0d\x0a"                    # tshark writes pcapng
    for back in (mb.read_pcap(path), mb.read_pcap(path, port=port)):
        assert [(e.data, e.role) for e in back] == [(e.data, e.guessed_role) for e in master.log]
        assert {e.dest for e in back if e.role == "request"} == {f"127.0.0.1:{port}"}
        assert all(back.explain(i).ok for i in range(len(back)))


# --- round trips -------------------------------------------------------------------------------------------
REGISTERS = st.lists(st.integers(0, 0xFFFF), min_size=1, max_size=125)


@st.composite
def transactions(draw, mode: str) -> list[mb.Traffic]:
    """A master's log: requests and their responses (or exception responses) at increasing times."""
    entries, now = [], draw(st.floats(0, 1e6))
    for tid in range(draw(st.integers(1, 12))):
        unit = draw(st.integers(1, 247))
        address = draw(st.integers(0, 65000))
        values = draw(REGISTERS)
        kind = draw(st.sampled_from(["read", "write", "single", "exception"]))
        if kind == "read":
            request = mb.ReadHoldingRegistersRequest(address=address, count=len(values))
            response = mb.ReadHoldingRegistersResponse(registers=values)
        elif kind == "write":
            request = mb.WriteMultipleRegistersRequest(address=address, values=values[:123])
            response = mb.WriteMultipleRegistersResponse(address=address, count=len(values[:123]))
        elif kind == "single":
            request = mb.WriteSingleRegisterRequest(address=address, value=values[0])
            response = mb.WriteSingleRegisterResponse(address=address, value=values[0])
        else:
            request = mb.ReadHoldingRegistersRequest(address=address, count=len(values))
            response = mb.ExceptionResponse(function=3, code=draw(st.integers(1, 11)))
        for pdu, direction in ((request, "tx"), (response, "rx")):
            if mode == "tcp":
                frame = mb.TcpFrame(transaction_id=tid, unit=unit, pdu=pdu)
            elif mode == "rtu":
                frame = mb.RtuFrame(unit=unit, pdu=pdu)
            else:
                frame = mb.AsciiFrame(unit=unit, pdu=pdu)
            now += draw(st.floats(1e-6, 10))
            entries.append(mb.Traffic(now, direction, mode, frame.encode(),
                                      role="request" if direction == "tx" else "response"))
    return entries


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.sampled_from(["tcp", "rtu", "ascii"]).flatmap(transactions))
def test_read_pcap_of_write_pcap_round_trips(tmp_path, frames):
    back = mb.read_pcap(mb.write_pcap(frames, tmp_path / "round.pcap"))
    assert [(e.time * 1e9).__round__() for e in back] == [(e.time * 1e9).__round__() for e in frames]
    assert [(e.direction, e.mode, e.data, e.role) for e in back] == \
           [(e.direction, e.mode, e.data, e.role) for e in frames]


def test_tcp_frames_split_over_segments_out_of_order_and_retransmitted_are_put_back(tmp_path):
    """A capture with the bytes cut, reordered and sent twice, as real TCP may: one frame each."""
    from scapy.layers.inet import IP, TCP
    from scapy.layers.l2 import Ether
    from scapy.utils import wrpcap

    frames = [mb.TcpFrame(transaction_id=t, unit=1, pdu=mb.ReadHoldingRegistersRequest(address=t, count=2))
              .encode() for t in range(1, 6)]
    stream = b"".join(frames)
    pieces = [(0, 5), (5, 12), (17, 30), (12, 20), (30, 60)]     # the fourth overlaps and fills a gap

    def packet(seq, data, flags="PA"):
        return (Ether() / IP(src="127.0.0.11", dst="127.0.0.12") /
                TCP(sport=40000, dport=1502, seq=seq, flags=flags) / data)

    packets = [packet(99, b"", "S")]
    packets += [packet(100 + start, stream[start:end]) for start, end in pieces]
    for i, p in enumerate(packets):
        p.time = 1.0 + i
    wrpcap(str(tmp_path / "pieces.pcap"), packets)
    back = mb.read_pcap(tmp_path / "pieces.pcap")
    assert [e.data for e in back] == frames
    assert [e.time for e in back] == [3.0, 5.0, 6.0, 6.0, 6.0]   # the packet that completed each frame
    assert {(e.source, e.dest, e.role) for e in back} == {("127.0.0.11:40000", "127.0.0.12:1502", "request")}
    # a gap the capture never filled: the frames after it are read, the note says what was missed
    wrpcap(str(tmp_path / "gap.pcap"), [p for i, p in enumerate(packets) if i != 2])
    back = mb.read_pcap(tmp_path / "gap.pcap", port=1502)
    assert [e.data for e in back] == frames[1:]       # the first frame lost 7 of its bytes
    assert back[0].note == "after a gap: the capture lacks 7 bytes of this direction"


def test_ipv6_and_linux_cooked_captures_are_read(tmp_path):
    from scapy.layers.inet import IP, TCP
    from scapy.layers.inet6 import IPv6
    from scapy.layers.l2 import CookedLinux, Ether
    from scapy.utils import wrpcap

    request = mb.TcpFrame(transaction_id=7, unit=1, pdu=mb.ReadHoldingRegistersRequest(address=3, count=2))
    response = mb.TcpFrame(transaction_id=7, unit=1, pdu=mb.ReadHoldingRegistersResponse(registers=[1, 2]))
    v6 = Ether() / IPv6(src="::1", dst="::1")
    wrpcap(str(tmp_path / "v6.pcap"), [
        v6 / TCP(sport=50000, dport=502, seq=10, flags="PA") / request.encode(),
        v6 / TCP(sport=502, dport=50000, seq=99, flags="PA") / response.encode(),
    ])
    back = mb.read_pcap(tmp_path / "v6.pcap")
    assert [(e.source, e.role, e.data) for e in back] == [
        ("[::1]:50000", "request", request.encode()), ("[::1]:502", "response", response.encode())]
    wrpcap(str(tmp_path / "sll.pcap"), [CookedLinux() / IP(src="127.0.0.1", dst="127.0.0.1") /
                                        TCP(sport=50000, dport=502, seq=10, flags="PA") / request.encode()])
    assert [e.data for e in mb.read_pcap(tmp_path / "sll.pcap")] == [request.encode()]


def test_a_gateways_serial_side_and_its_bus_are_captured(tmp_path):
    bus = mb.loopback_serial(course_slave(), baudrate=19200)
    with mb.TcpGateway(bus, timeout=0.2) as gateway, mb.tcp_link(*gateway.address[:2]) as link:
        mb.Master(link).read_holding_registers(unit=1, address=0, count=3)
    for log in (gateway.master.log, bus.monitor):
        back = mb.read_pcap(mb.write_pcap(log, tmp_path / "gateway.pcap"))
        assert [(e.mode, e.role, e.data) for e in back] == [("rtu", e.guessed_role, e.data) for e in log]
        assert back.explain(1).frame.pdu.registers == (11, 22, 33)


# --- damaged files -----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def good_captures(tcp_log, rtu_monitor, tmp_path_factory) -> list[bytes]:
    folder = tmp_path_factory.mktemp("good")
    files = [mb.write_pcap(tcp_log, folder / "tcp.pcap").read_bytes(),
             mb.write_pcap(rtu_monitor, folder / "rtu.pcap").read_bytes()]
    if TSHARK:
        run_tshark("-r", str(folder / "tcp.pcap"), "-F", "pcapng", "-w", str(folder / "tcp.pcapng"))
        files.append((folder / "tcp.pcapng").read_bytes())
    return files


@st.composite
def damaged(draw, good: list[bytes]) -> bytes:
    data = bytearray(draw(st.sampled_from(good)))
    how = draw(st.sampled_from(["truncate", "flip", "huge", "random", "splice"]))
    if how == "truncate":
        del data[draw(st.integers(0, len(data) - 1)):]
    elif how == "flip":
        for _ in range(draw(st.integers(1, 8))):
            data[draw(st.integers(0, len(data) - 1))] ^= 1 << draw(st.integers(0, 7))
    elif how == "huge":
        at = draw(st.integers(0, len(data) - 4))
        data[at:at + 4] = draw(st.sampled_from([b"\xff\xff\xff\xff", b"\x7f\xff\xff\xff", b"\0\0\0\x80"]))
    elif how == "random":
        data = bytearray(data[:draw(st.integers(0, 24))] + draw(st.binary(max_size=400)))
    else:
        at = draw(st.integers(0, len(data)))
        data[at:at] = draw(st.binary(min_size=1, max_size=64))
    return bytes(data)


def test_damaged_files_raise_only_capture_errors(good_captures, tmp_path):
    @settings(max_examples=300, deadline=None)
    @given(damaged(good_captures))
    def check(data):
        path = tmp_path / "damaged.pcap"
        path.write_bytes(data)
        try:
            frames = mb.read_pcap(path)
        except mb.ModbusError as exc:
            assert str(exc) and "Traceback" not in str(exc)
            return
        for i in range(len(frames)):
            frames.explain(i)

    check()


@pytest.mark.parametrize("data, words", [
    (b"", "the file is empty"),
    (b"GIF89a....", "not a capture file"),
    (b"\x1f\x8b\x08\x00", "gunzip"),
    (b"\xd4\xc3\xb2\xa1\x02\x00", "file header is damaged"),
])
def test_what_is_not_a_capture_is_named(tmp_path, data, words):
    path = tmp_path / "bad.pcap"
    path.write_bytes(data)
    with pytest.raises(mb.CaptureError, match=words):
        mb.read_pcap(path)


def test_a_cut_short_capture_and_a_huge_length_say_where(tcp_log, tmp_path):
    data = mb.write_pcap(tcp_log, tmp_path / "good.pcap").read_bytes()
    (tmp_path / "cut.pcap").write_bytes(data[:-10])
    with pytest.raises(mb.CaptureError, match=r"ends inside packet 46 .*cut short"):
        mb.read_pcap(tmp_path / "cut.pcap")
    huge = bytearray(data)
    huge[24 + 8:24 + 12] = b"\xff\xff\xff\x7f"                    # the first record's captured length
    (tmp_path / "huge.pcap").write_bytes(bytes(huge))
    with pytest.raises(mb.CaptureError, match=r"packet 1 .*claims 2147483647 bytes"):
        mb.read_pcap(tmp_path / "huge.pcap")
    with pytest.raises(mb.CaptureError, match="cannot open"):
        mb.read_pcap(tmp_path / "missing.pcap")


@pytest.mark.parametrize("source, words", [
    ([], "no frames"),
    ("log.pcap", "swapped"),
    ([(0.0, "tx", "tcp", b"\x00"), (0.1, "rx", "rtu", b"\x01")], "one link type"),
    ([(-1.0, "tx", "rtu", b"\x01")], "seconds from 0"),
    ([(0.0, "up", "rtu", b"\x01")], "direction"),
    ([(0.0, "tx", "rtu")], "expected a Traffic entry"),
    ([(0.0, "tx", "x25", b"\x01")], "mode"),
])
def test_write_pcap_refuses_with_a_reason(tmp_path, source, words):
    with pytest.raises(mb.CaptureError, match=words):
        mb.write_pcap(source, tmp_path / "x.pcap")


def test_bad_paths_ports_and_endpoints_are_named(tmp_path):
    frames = [(0.0, "tx", "tcp", b"\x00\x01\x00\x00\x00\x02\x01\x07")]
    with pytest.raises(mb.CaptureError, match="path is a str or a Path"):
        mb.write_pcap(frames, None)
    with pytest.raises(mb.CaptureError, match="path is a str or a Path"):
        mb.read_pcap(3)
    with pytest.raises(mb.CaptureError, match="cannot write"):
        mb.write_pcap(frames, tmp_path / "no such folder" / "x.pcap")
    with pytest.raises(mb.CaptureError, match="two ends"):
        mb.write_pcap(frames, tmp_path / "x.pcap", client=("127.0.0.2", 502))
    with pytest.raises(mb.CaptureError, match="IPv4 address, port"):
        mb.write_pcap(frames, tmp_path / "x.pcap", server=("localhost", 502))
    with pytest.raises(mb.CaptureError, match="port must be"):
        mb.read_pcap(mb.write_pcap(frames, tmp_path / "x.pcap"), port=70000)
    # another pair of addresses is another connection, and port= names the server
    back = mb.read_pcap(mb.write_pcap(frames, tmp_path / "y.pcap", client=("127.1.1.1", 40000),
                                      server=("127.1.1.2", 1502)), port=1502)
    assert [(e.source, e.dest, e.role) for e in back] == [("127.1.1.1:40000", "127.1.1.2:1502", "request")]


def test_reading_is_linear_in_the_size_of_the_file(tmp_path):
    """Ten times the traffic (and ten times the junk between frames) takes about ten times the work."""
    def capture(count: int) -> Path:
        frames = []
        for i in range(count):
            request = mb.TcpFrame(transaction_id=i % 65536, unit=1,
                                  pdu=mb.ReadHoldingRegistersRequest(address=0, count=1)).encode()
            frames.append(mb.Traffic(i * 0.001, "tx", "tcp", b"\xff" * 40 + request))  # junk, then a frame
        return mb.write_pcap(frames, tmp_path / f"n{count}.pcap")

    def cost(path: Path) -> tuple[float, int]:
        start = time.process_time()
        frames = mb.read_pcap(path, port=502)
        return time.process_time() - start, len(frames)

    small, n_small = cost(capture(150))
    large, n_large = cost(capture(1500))
    assert (n_small, n_large) == (150, 1500)
    assert large < 10 * small * 3 + 0.5, (small, large)     # generous: the machine is shared


def test_records_carry_the_serial_link_types(rtu_monitor, tmp_path):
    from scapy.utils import RawPcapReader

    with RawPcapReader(str(mb.write_pcap(rtu_monitor, tmp_path / "rtu.pcap"))) as reader:
        assert reader.linktype == LINKTYPE_RTU
    link = mb.loopback_serial(course_slave(), mode="ascii")
    mb.Master(link).read_coils(1, 0, 3)
    with RawPcapReader(str(mb.write_pcap(link.monitor, tmp_path / "ascii.pcap"))) as reader:
        assert reader.linktype == LINKTYPE_ASCII


# --- pcapng cut short, and blocks that lie -----------------------------------------------------------------
def _pcapng(packets: list[bytes], linktype: int = LINKTYPE_RTU) -> tuple[bytes, list[int]]:
    """A little-endian pcapng file (a section header, one interface, an enhanced packet block per packet)
    and the byte offset where each block ends."""
    def block(kind: int, body: bytes) -> bytes:
        body += b"\0" * (-len(body) % 4)
        return struct.pack("<II", kind, len(body) + 12) + body + struct.pack("<I", len(body) + 12)

    blocks = [block(0x0A0D0D0A, struct.pack("<IHHq", 0x1A2B3C4D, 1, 0, -1)),
              block(1, struct.pack("<HHI", linktype, 0, 0))]
    blocks += [block(6, struct.pack("<IIIII", 0, 0, i, len(p), len(p)) + p) for i, p in enumerate(packets)]
    ends, at = [], 0
    for b in blocks:
        at += len(b)
        ends.append(at)
    return b"".join(blocks), ends


def test_a_pcapng_cut_short_at_any_byte_is_a_capture_error(tmp_path):
    """Cut anywhere but between two blocks, a pcapng raises CaptureError, as a cut pcap does; cut between
    two blocks, it is a shorter capture and reads as one."""
    master = mb.Master(mb.loopback_serial(course_slave()))
    for address in range(3):
        master.read_holding_registers(unit=1, address=address, count=2)
    packets = [entry.data for entry in master.link.monitor]
    data, ends = _pcapng(packets)
    path = tmp_path / "cut.pcapng"
    path.write_bytes(data)
    assert [e.data for e in mb.read_pcap(path)] == packets
    for cut in range(len(data)):
        path.write_bytes(data[:cut])
        if cut in ends:
            assert [e.data for e in mb.read_pcap(path)] == packets[:max(0, ends.index(cut) - 1)]
            continue
        with pytest.raises(mb.CaptureError):
            mb.read_pcap(path)
    path.write_bytes(data[:ends[3] + 10])
    with pytest.raises(mb.CaptureError, match=rf"ends inside block 5 \(at byte {ends[3]}\).*cut short"):
        mb.read_pcap(path)


def test_a_packet_block_whose_captured_length_runs_past_it_is_refused(tmp_path):
    frame = mb.RtuFrame(unit=1, pdu=mb.ReadHoldingRegistersRequest(address=0, count=2)).encode()
    data, ends = _pcapng([frame, frame])
    damaged = bytearray(data)
    damaged[ends[1] + 20:ends[1] + 24] = struct.pack("<I", 200)  # the first packet's captured length
    path = tmp_path / "liar.pcapng"
    path.write_bytes(bytes(damaged))
    with pytest.raises(mb.CaptureError, match=rf"block 3 \(at byte {ends[1]}\).*200 captured bytes"):
        mb.read_pcap(path)


# --- TCP put back in order when the capture lacks the start, or holds too much out of order ----------------
def _tcp_capture(path: Path, segments: list[tuple[int, bytes]], syn: int | None = None) -> Path:
    """A capture of segments (sequence number, bytes), 127.0.0.11:40000 to 127.0.0.12:502, in this order."""
    from scapy.layers.inet import IP, TCP
    from scapy.layers.l2 import Ether
    from scapy.utils import wrpcap

    def packet(seq, data, flags="PA"):
        return Ether() / IP(src="127.0.0.11", dst="127.0.0.12") / TCP(sport=40000, dport=502, seq=seq,
                                                                       flags=flags) / data

    packets = [packet(syn, b"", "S")] if syn is not None else []
    packets += [packet(seq, data) for seq, data in segments]
    for i, p in enumerate(packets):
        p.time = 1.0 + i
    wrpcap(str(path), packets)
    return path


def _requests(count: int) -> list[bytes]:
    return [mb.TcpFrame(transaction_id=t, unit=1, pdu=mb.ReadHoldingRegistersRequest(address=t, count=2))
            .encode() for t in range(count)]


def test_without_a_syn_two_swapped_first_segments_keep_both_frames(tmp_path):
    first, second, third = _requests(3)
    swapped = _tcp_capture(tmp_path / "swapped.pcap", [(112, second), (100, first), (124, third)])
    back = mb.read_pcap(swapped)
    assert [e.data for e in back] == [first, second, third]
    assert [e.time for e in back] == [2.0, 2.0, 3.0]
    assert all(not e.note for e in back)
    # the first segment seen starts inside a frame: its bytes are put back behind the ones before them
    stream = first + second
    cut = _tcp_capture(tmp_path / "cut.pcap", [(105, stream[5:]), (100, stream[:5])])
    back = mb.read_pcap(cut)
    assert [e.data for e in back] == [first, second] and all(not e.note for e in back)


def test_past_256_held_segments_the_notes_say_what_happened(tmp_path):
    frames = _requests(300)
    late = [(1000 + 12 * i, f) for i, f in enumerate(frames)][1:] + [(1000, frames[0])]
    back = mb.read_pcap(_tcp_capture(tmp_path / "late.pcap", late, syn=999))
    assert [e.data for e in back] == frames[1:]
    notes = [(i, e.note) for i, e in enumerate(back) if e.note]
    assert len(notes) == 2, notes
    assert notes[0][0] == 0 and "12 bytes of this direction had not arrived" in notes[0][1]
    assert "256" in notes[0][1] and "lacks" not in notes[0][1]
    assert notes[1][0] == len(back) - 1 and "12 bytes of this direction arrived after" in notes[1][1]
    assert "not read" in notes[1][1]
    # a gap the capture never fills is what the capture lacks
    back = mb.read_pcap(_tcp_capture(tmp_path / "lost.pcap", late[:-1], syn=999))
    assert [e.data for e in back] == frames[1:]
    assert [e.note for e in back if e.note] == [notes[0][1]]
