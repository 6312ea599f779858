"""The command line, run as a real subprocess: ``python -m modbus_edu`` (and the ``modbus-edu`` script).

Every subcommand, its ``--help``, and every kind of bad input: the exit status, the one-line message
on stderr, and never a traceback.  ``serve`` runs as a real server on a loopback port, read by a
pymodbus client; ``poll`` reads the course's own servers.
"""

from __future__ import annotations

import contextlib
import csv
import json
import os
import select
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path

import pytest

import modbus_edu as mb
from modbus_edu import security
from modbus_edu.devices.meter import METER_MAP, TRIAL_ENERGY_KWH, TRIALS, PowerMeter
from modbus_edu.framing import RtuFrame
from modbus_edu.links.serial import SerialServer, TcpSerialPort
from modbus_edu.links.tcp import TcpServer
from modbus_edu.pdu import ReadHoldingRegistersRequest, ReadHoldingRegistersResponse
from modbus_edu.slave import Slave

CLI = [sys.executable, "-m", "modbus_edu"]
ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONUNBUFFERED": "1"}


def _run(args: tuple[str, ...], stdin: str | None = None, timeout: float = 60) -> subprocess.CompletedProcess:
    return subprocess.run([*CLI, *args], input=stdin, capture_output=True, text=True, timeout=timeout,
                          cwd=ROOT, env=ENV)


# Commands that need no server are known when this module is imported: they are all started at once,
# a few at a time in parallel (each is a fresh Python process, most of whose time is start-up).
_STATIC: dict[tuple[tuple[str, ...], str | None], Future] = {}
_POOL = ThreadPoolExecutor(max_workers=6)


def static(*args: str, stdin: str | None = None) -> tuple[str, ...]:
    """Register a command whose result does not depend on anything running; returns ``args``."""
    key = (args, stdin)
    if key not in _STATIC:
        _STATIC[key] = None  # type: ignore[assignment]
    return args


@pytest.fixture(scope="module", autouse=True)
def _start_static_commands(request):
    selected = sum(1 for item in request.session.items if getattr(item, "module", None) is request.module)
    if selected >= 10:  # worth it only when most of this module runs (not for one test picked by -k)
        for key in _STATIC:
            _STATIC[key] = _POOL.submit(_run, *key)
    yield
    _POOL.shutdown(wait=True)


def run(*args: str, stdin: str | None = None) -> subprocess.CompletedProcess:
    future = _STATIC.get((args, stdin))
    if future is not None:
        return future.result()
    return _run(args, stdin)


def ok(*args: str, stdin: str | None = None) -> str:
    result = run(*args, stdin=stdin)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    return result.stdout


def fails(
    *args: str, code: int = 1, message: str = "", stdin: str | None = None
) -> subprocess.CompletedProcess:
    """Run, and check the contract for bad input: exit status, one line on stderr, no traceback."""
    result = run(*args, stdin=stdin)
    assert result.returncode == code, (result.returncode, result.stdout, result.stderr)
    assert "Traceback" not in result.stderr and "Traceback" not in result.stdout
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("modbus-edu: error: "), lines[0]
    assert message.lower() in lines[0].lower(), lines[0]
    return result


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# the fixed commands of the tests below (started together, see ``static``)
for _args, _stdin in [
    (("--help",), None),
    *(((sub, "--help"), None) for sub in ("crc", "lrc", "decode", "build", "serve", "poll")),
    (("crc", "01", "03", "00", "00", "00", "01"), None),
    (("crc", "--text", "123456789"), None),
    (("crc", "-v", "0103"), None),
    (("lrc", "05 06 10 01 02 00"), None),
    (("lrc", "050310000002"), None),
    (("crc",), None),
    (("decode", "01", "03", "00", "00", "00", "01", "84", "0A"), None),
    (("decode", "01 18 00 00 00 06 01 03 00 00 00 01"), None),
    (("decode", ":050304FF0600648B"), None),
    (("decode", "--json", "--mode", "rtu", "--role", "response", "01 03 02 04 D2 3A D9"), None),
    (("decode", "-"), "01 03 00 00 00 01 84 0A\n01 03 02 04 D2 3A D9\n"),
    (("decode", "01 03 00 00 00 01 84 0B"), None),
    (("decode", "--json", "01 03 00 00 00 01 84 0B"), None),
    (("build", "--mode", "rtu", "--unit", "1", "--function", "3", "--address", "0", "--count", "1"), None),
    (("build", "--mode", "tcp", "--unit", "1", "--function", "read_holding_registers", "--address", "0",
      "--count", "1", "--transaction-id", "0x0118"), None),
    (("build", "--mode", "ascii", "--unit", "5", "--function", "6", "--address", "0x1001",
      "--value", "0x0200"), None),
    (("build", "--function", "16", "--address", "1", "--values", "10,20"), None),
    (("build", "--function", "5", "--address", "0x00AC", "--value", "on"), None),
    (("build", "--function", "15", "--address", "0", "--values", "1,0,1"), None),
    (("build", "--function", "3", "--role", "response", "--values", "0x04D2"), None),
    (("build", "--function", "3", "--role", "response", "--exception", "2"), None),
    (("build", "--json", "--function", "4", "--address", "0", "--count", "2"), None),
]:
    static(*_args, stdin=_stdin)


def register(prefix: tuple[str, ...], cases: list, stdin: str | None = None) -> list:
    """Register the commands of parametrized cases ``(args, ...)`` as static; return the cases."""
    for case in cases:
        static(*prefix, *case[0], stdin=stdin)
    return cases


def _readline(stream, timeout: float) -> str:
    ready, _, _ = select.select([stream], [], [], timeout)
    assert ready, "the server printed nothing in time"
    return stream.readline()


@contextlib.contextmanager
def serving(*args: str, port: int = 0) -> Iterator[tuple[subprocess.Popen, int]]:
    """``modbus-edu serve ... --tcp 127.0.0.1:PORT`` as a subprocess; yields it and the port it listens on.

    Stops it with SIGINT (Ctrl-C) and checks that it exits cleanly with status 0.
    """
    proc = subprocess.Popen([*CLI, "serve", *args, "--tcp", f"127.0.0.1:{port}"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=ROOT, env=ENV)
    try:
        line = _readline(proc.stdout, 20)
        assert "serving" in line and "127.0.0.1:" in line, line + proc.stderr.read()
        bound = int(line.split("127.0.0.1:")[1].split(";")[0])
        if port:
            assert bound == port
        yield proc, bound
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=15)
        assert proc.returncode == 0, err
        assert "Traceback" not in err
        assert "requests:" in err  # the live count
        assert out.startswith("stopped:") or "stopped:" in out
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


# --- help ------------------------------------------------------------------------------------------
def test_help_for_the_program_and_every_subcommand():
    text = ok("--help")
    for sub in ("crc", "lrc", "decode", "build", "serve", "poll"):
        assert sub in text
    for sub, option in (("crc", "--text"), ("lrc", "HEX"), ("decode", "--json"), ("build", "--function"),
                        ("serve", "--tcp"), ("poll", "--csv")):
        text = ok(sub, "--help")
        assert text.startswith(f"usage: modbus-edu {sub}") and option in text


def test_console_script_is_installed():
    script = shutil.which("modbus-edu", path=str(Path(sys.executable).parent))
    assert script is not None, "pip install -e . creates the modbus-edu script"
    result = subprocess.run([script, "crc", "--text", "123456789"], capture_output=True, text=True,
                            timeout=30)
    assert result.returncode == 0 and "0x4B37" in result.stdout


# --- crc, lrc ---------------------------------------------------------------------------------------
def test_crc_value_and_wire_order():
    out = ok("crc", "01", "03", "00", "00", "00", "01")
    assert "0x0A84" in out
    assert "low byte first: 84 0A" in out
    assert "01 03 00 00 00 01 84 0A" in out
    assert "0x4B37" in ok("crc", "--text", "123456789")
    assert "37 4B" in ok("crc", "--text", "123456789")


def test_crc_verbose_shows_the_table_steps():
    out = ok("crc", "-v", "0103")
    assert "table value" in out
    assert len([line for line in out.splitlines() if line.startswith("  01") or line.startswith("  03")]) == 2


def test_lrc_value_and_frame():
    out = ok("lrc", "05 06 10 01 02 00")
    assert "0xE2" in out and ":050610010200E2" in out
    assert "0xE6" in ok("lrc", "050310000002")


@pytest.mark.parametrize(
    "args, message",
    register((), [
        (["crc", "010"], "odd number of hex digits"),
        (["crc", "01", "0G"], "not a hex digit"),
        (["lrc", ":050610010200E2"], "without ':'"),
        (["lrc", "0x"], "not followed by hex digits"),
    ]),
)
def test_crc_lrc_bad_input(args, message):
    fails(*args, message=message)


def test_crc_without_bytes_is_a_usage_error():
    fails("crc", code=2, message="the following arguments are required")


# --- decode -----------------------------------------------------------------------------------------
def test_decode_rtu_table():
    out = ok("decode", "01", "03", "00", "00", "00", "01", "84", "0A")
    assert out.startswith("RTU request: unit 1, Read Holding Registers, address 0, count 1")
    assert "starting address" in out and "CRC" in out and "correct" in out


def test_decode_detects_tcp_and_ascii():
    out = ok("decode", "01 18 00 00 00 06 01 03 00 00 00 01")  # source 000's MBAP request
    assert out.startswith("TCP request: transaction 280")
    out = ok("decode", ":050304FF0600648B")  # source 004's response
    assert out.startswith("ASCII response: unit 5")


def test_decode_json():
    data = json.loads(ok("decode", "--json", "--mode", "rtu", "--role", "response", "01 03 02 04 D2 3A D9"))
    assert data["ok"] is True and data["role"] == "response"
    assert data["frame"]["fields"]["registers"] == [1234]
    assert [row["field"] for row in data["rows"]][0].startswith("unit")


def test_decode_frames_from_stdin():
    out = ok("decode", "-", stdin="01 03 00 00 00 01 84 0A\n01 03 02 04 D2 3A D9\n")
    assert "RTU request" in out and "RTU response" in out


def test_decode_bad_crc_shows_the_table_and_fails():
    result = fails("decode", "01 03 00 00 00 01 84 0B", message="CRC mismatch")
    assert "mismatch: computed 0x0A84" in result.stdout
    result = fails("decode", "--json", "01 03 00 00 00 01 84 0B", message="CRC mismatch")
    assert json.loads(result.stdout)["error_type"] == "CrcError"


@pytest.mark.parametrize(
    "args, code, message",
    register((), [
        (["decode", "010300000001840"], 1, "odd number of hex digits"),
        (["decode", "01 03 zz"], 1, "not a hex digit"),
        (["decode", "01 09 C0 26"], 1, "function code 0x09"),
        (["decode", "--mode", "foo", "01"], 2, "invalid choice"),
        (["decode", "--role", "both", "01"], 2, "invalid choice"),
        (["decode", "-"], 1, "no frames"),
    ], stdin=""),
)
def test_decode_bad_input(args, code, message):
    fails(*args, code=code, message=message, stdin="")


# --- build ------------------------------------------------------------------------------------------
def test_build_rtu_tcp_ascii():
    out = ok("build", "--mode", "rtu", "--unit", "1", "--function", "3", "--address", "0", "--count", "1")
    assert out.splitlines()[0] == "01 03 00 00 00 01 84 0A"
    assert "RTU request" in out
    out = ok("build", "--mode", "tcp", "--unit", "1", "--function", "read_holding_registers",
             "--address", "0", "--count", "1", "--transaction-id", "0x0118")
    assert out.splitlines()[0] == "01 18 00 00 00 06 01 03 00 00 00 01"
    out = ok("build", "--mode", "ascii", "--unit", "5", "--function", "6", "--address", "0x1001",
             "--value", "0x0200")
    assert out.splitlines()[0] == ":050610010200E2\\r\\n"


def test_build_writes_and_responses():
    out = ok("build", "--function", "16", "--address", "1", "--values", "10,20")
    assert out.splitlines()[0] == "01 10 00 01 00 02 04 00 0A 00 14 12 6E"
    out = ok("build", "--function", "5", "--address", "0x00AC", "--value", "on")
    assert out.splitlines()[0].startswith("01 05 00 AC FF 00")
    out = ok("build", "--function", "15", "--address", "0", "--values", "1,0,1")
    assert out.splitlines()[0].startswith("01 0F 00 00 00 03 01 05")
    out = ok("build", "--function", "3", "--role", "response", "--values", "0x04D2")
    assert out.splitlines()[0] == "01 03 02 04 D2 3A D9"
    out = ok("build", "--function", "3", "--role", "response", "--exception", "2")
    assert out.splitlines()[0] == "01 83 02 C0 F1"
    data = json.loads(ok("build", "--json", "--function", "4", "--address", "0", "--count", "2"))
    assert data["hex"].startswith("01 04 00 00 00 02") and data["dissection"]["ok"] is True


@pytest.mark.parametrize(
    "args, code, message",
    register(("build",), [
        (["--function", "9", "--address", "0", "--count", "1"], 1, "function 9"),
        (["--function", "read_everything"], 1, "unknown function"),
        (["--function", "3", "--address", "0"], 1, "needs --count"),
        (["--function", "3", "--address", "0", "--count", "200"], 1, "quantity"),
        (["--function", "6", "--address", "0", "--value", "70000"], 1, "0..65535"),
        (["--function", "5", "--address", "0", "--value", "maybe"], 1, "on/off"),
        (["--function", "3", "--address", "0", "--count", "1", "--unit", "248"], 1, "--unit"),
        (["--function", "3", "--exception", "2"], 1, "--role response"),
        (["--address", "0"], 2, "--function"),
        (["--mode", "udp", "--function", "3"], 2, "invalid choice"),
    ]),
)
def test_build_bad_input(args, code, message):
    fails("build", *args, code=code, message=message)


# --- serve, read by pymodbus -------------------------------------------------------------------------
def test_serve_meter_read_by_pymodbus():
    from pymodbus.client import ModbusTcpClient

    with serving("meter", "--trial", "2") as (_, port):
        client = ModbusTcpClient("127.0.0.1", port=port, timeout=3)
        assert client.connect()
        try:
            for entry in METER_MAP:
                rr = client.read_holding_registers(entry.address, count=2, device_id=1)
                assert not rr.isError(), entry.name
                raw = client.convert_from_registers(rr.registers, data_type=client.DATATYPE.UINT32,
                                                    word_order="big")
                expected = TRIAL_ENERGY_KWH[2] if entry.name == "kWh" else TRIALS[2][entry.name]
                assert raw / entry.scale == pytest.approx(expected, abs=1e-9), entry.name
            rr = client.read_holding_registers(0x04, count=1, device_id=1)
            assert rr.isError() and rr.exception_code == 2
        finally:
            client.close()


def test_serve_arduino_read_by_pymodbus_on_a_chosen_port():
    from pymodbus.client import ModbusTcpClient

    port = free_port()
    with serving("arduino", "--unit", "3", port=port) as (_, bound):
        client = ModbusTcpClient("127.0.0.1", port=bound, timeout=3)
        assert client.connect()
        try:
            assert not client.write_coil(1, True, device_id=3).isError()
            assert client.read_coils(0, count=3, device_id=3).bits[:3] == [False, True, False]
            assert not client.write_coils(0, [True, True, False], device_id=3).isError()
            assert client.read_coils(0, count=3, device_id=3).bits[:3] == [True, True, False]
            assert not client.read_discrete_inputs(0, count=2, device_id=3).isError()
            pots = client.read_input_registers(0, count=2, device_id=3).registers
            assert all(0 <= p <= 1023 for p in pots)
            assert not client.write_register(1, 42, device_id=3).isError()
            assert not client.write_registers(0, [800, 43], device_id=3).isError()
            assert client.read_holding_registers(0, count=2, device_id=3).registers == [800, 43]
            rr = client.read_holding_registers(2, count=1, device_id=3)  # 40003 was never added
            assert rr.isError() and rr.exception_code == 2
        finally:
            client.close()


def test_serve_bank_and_sigterm_also_stops_cleanly():
    proc = subprocess.Popen([*CLI, "serve", "bank", "--tcp", "0"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=ROOT, env=ENV)
    try:
        line = _readline(proc.stdout, 20)
        assert "Modbus/TCP 127.0.0.1:" in line  # a bare port listens on loopback only
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=15)
        assert proc.returncode == 0 and "Traceback" not in err
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_serve_meter_on_a_serial_url():
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(1)
    listener.settimeout(20)
    port = listener.getsockname()[1]
    proc = subprocess.Popen([*CLI, "serve", "meter", "--serial", f"socket://127.0.0.1:{port}"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, env=ENV)
    try:
        conn, _ = listener.accept()
        line = _readline(proc.stdout, 20)
        assert "19200 baud 8N1, RTU" in line
        conn.settimeout(10)
        conn.sendall(RtuFrame(unit=1, pdu=ReadHoldingRegistersRequest(address=0, count=4)).encode())
        expected = RtuFrame(unit=1, pdu=ReadHoldingRegistersResponse(registers=[0, 4036, 4, 0xA704])).encode()
        reply = b""
        while len(reply) < len(expected):
            chunk = conn.recv(256)
            assert chunk
            reply += chunk
        assert reply == expected
        conn.close()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=15)
        assert proc.returncode == 0 and "Traceback" not in err
    finally:
        listener.close()
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


@pytest.mark.parametrize(
    "args, code, message",
    register(("serve",), [
        (["meter", "--tcp", "127.0.0.1:99999"], 1, "bad port 99999"),
        (["meter", "--tcp", "localhost:http"], 1, "bad address"),
        (["meter", "--serial", "loop://", "--baud", "12"], 2, "not a serial speed"),
        (["meter", "--trial", "3"], 2, "invalid choice"),
        (["toaster"], 2, "invalid choice"),
        (["meter", "--tcp", "0", "--serial", "loop://"], 1, "choose one wire"),
        (["arduino", "--unit", "0"], 1, "--unit"),
        (["meter", "--serial", "/dev/no-such-port"], 1, "cannot open serial port"),
    ]),
)
def test_serve_bad_settings(args, code, message):
    fails("serve", *args, code=code, message=message)


def test_serve_on_a_port_in_use_fails():
    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen(1)
        fails("serve", "meter", "--tcp", f"127.0.0.1:{busy.getsockname()[1]}", message="cannot listen")


# --- poll ---------------------------------------------------------------------------------------------
@pytest.fixture()
def meter_server():
    with TcpServer(PowerMeter(trial=1)) as server:
        yield server.address[1]


def test_poll_prints_values_statistics_and_csv(meter_server, tmp_path):
    log = tmp_path / "poll.csv"
    result = run("poll", "--tcp", f"127.0.0.1:{meter_server}", "--unit", "1", "--function", "3",
                 "--address", "0", "--count", "4", "--format", "uint32_ABCD", "--polls", "3",
                 "--interval", "0.05", "--csv", str(log), "--verbose")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "#1 [0] 4036  [2] 304900"  # VL1 403.6 V x 10, AL1 304 900 mA
    assert lines[-1].startswith("stats: requests 3, valid 3, timeouts 0")
    assert result.stderr.count("tx -> ") == 3 and result.stderr.count("rx <- ") == 3
    with log.open() as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["time", "poll", "status", "0", "2"]
    assert [r[1:] for r in rows[1:]] == [[str(i), "ok", "4036", "304900"] for i in (1, 2, 3)]


def test_poll_hex_and_bits(meter_server):
    out = ok("poll", "--tcp", f"127.0.0.1:{meter_server}", "--address", "0x30", "--count", "2",
             "--format", "hex", "--polls", "1")
    assert out.startswith("#1 [48] 0x0000  [49] 0x0010")


def test_poll_exception_response_is_reported(meter_server):
    result = fails("poll", "--tcp", f"127.0.0.1:{meter_server}", "--address", "4", "--count", "1",
                   "--polls", "2", "--interval", "0", message="no valid response in 2 polls")
    assert "#1 exception 02: illegal data address" in result.stdout
    assert "exceptions 2" in result.stdout


def test_poll_timeout_is_counted():
    with socket.socket() as mute:  # accepts connections, never answers
        mute.bind(("127.0.0.1", 0))
        mute.listen(1)
        result = fails("poll", "--tcp", f"127.0.0.1:{mute.getsockname()[1]}", "--polls", "1",
                       "--timeout", "0.2", message="no valid response")
    assert "#1 timeout" in result.stdout and "timeouts 1" in result.stdout


def test_poll_over_a_serial_url():
    with SerialServer(PowerMeter(trial=2), TcpSerialPort("127.0.0.1", 0), baudrate=19200) as server:
        host, port = server.port.address
        out = ok("poll", "--serial", f"socket://{host}:{port}", "--baud", "19200", "--address", "0",
                 "--count", "2", "--polls", "1", "--timeout", "2")
    assert out.startswith("#1 [0] 0  [1] 4126")


def test_poll_connection_refused():
    fails("poll", "--tcp", f"127.0.0.1:{free_port()}", "--polls", "1", message="connection refused")


# (these fail before connecting: port 1 is never tried)
@pytest.mark.parametrize(
    "args, code, message",
    register(("poll",), [
        (["--tcp", "no-such-host.invalid:502"], 1, "unknown host"),
        (["--tcp", "127.0.0.1"], 1, "bad address"),
        (["--serial", "/dev/no-such-port"], 1, "cannot open serial port"),
        ([], 1, "give --tcp"),
        (["--tcp", "127.0.0.1:1", "--function", "6"], 1, "use --function 1, 2, 3 or 4"),
        (["--tcp", "127.0.0.1:1", "--function", "99"], 1, "function 99"),
        (["--tcp", "127.0.0.1:1", "--format", "float16_ABCD"], 1, "unknown --format"),
        (["--tcp", "127.0.0.1:1", "--count", "126"], 1, "--count"),
        (["--tcp", "127.0.0.1:1", "--unit", "256"], 1, "--unit"),
        (["--tcp", "127.0.0.1:1", "--timeout", "0"], 1, "--timeout"),
        (["--tcp", "127.0.0.1:1", "--interval", "x"], 2, "invalid float"),
        (["--serial", "loop://", "--parity", "X"], 2, "invalid choice"),
    ]),
)
def test_poll_bad_input(args, code, message):
    fails("poll", *args, code=code, message=message)


def test_keyboard_interrupt_during_poll_prints_statistics_and_exits_0(meter_server):
    proc = subprocess.Popen([*CLI, "poll", "--tcp", f"127.0.0.1:{meter_server}", "--interval", "0.05"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, env=ENV)
    try:
        assert _readline(proc.stdout, 20).startswith("#1 [0] 0")
        time.sleep(0.2)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=15)
        assert proc.returncode == 0, err
        assert "Traceback" not in err
        assert out.splitlines()[-1].startswith("stats: requests")
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


@pytest.mark.parametrize(("args", "words"), [
    (("crc", "--text", "é€"), "is not ASCII"),
    (("poll", "--tcp", "127.0.0.1:1", "--timeout", "inf"), "--timeout must be a number of seconds"),
    (("poll", "--tcp", "127.0.0.1:1", "--timeout", "1e300"), "--timeout must be a number of seconds"),
    (("poll", "--tcp", "127.0.0.1:1", "--interval", "nan"), "--interval must be a number of seconds"),
    (("poll", "--tcp", "127.0.0.1:1", "--interval", "inf"), "--interval must be a number of seconds"),
    (("poll", "--tcp", "127.0.0.1:1", "--address", "65535", "--count", "2"), "runs past the last address"),
    (("serve", "bank", "--tcp", "256.1.1.1:5020"), "cannot listen"),
])
def test_bad_numbers_and_hosts_are_refused_up_front_in_one_line(args, words):
    result = run(*args)
    assert result.returncode != 0 and "Traceback" not in result.stderr
    assert words in result.stderr and "listening on" not in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr


def test_serve_in_ascii_mode_announces_the_7_data_bits_it_opens():
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(1)
    listener.settimeout(20)
    port = listener.getsockname()[1]
    proc = subprocess.Popen([*CLI, "serve", "bank", "--mode", "ascii", "--serial", f"socket://127.0.0.1:{port}"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT, env=ENV)
    try:
        conn, _ = listener.accept()
        line = _readline(proc.stdout, 20)
        assert "9600 baud 7E1, ASCII" in line, line  # 7E1: what Modbus ASCII devices use by default
        conn.close()
    finally:
        listener.close()
        if proc.poll() is None:
            proc.kill()
        proc.communicate()


def test_decode_reads_standard_input_line_by_line_and_refuses_a_huge_line():
    frames = "01 03 00 00 00 01 84 0A\n" * 20_000  # 480 kB: decoded as it streams, in flat memory
    result = run("decode", "-", "--mode", "rtu", stdin=frames)
    assert result.returncode == 0 and result.stdout.count("RTU request") == 20_000
    huge = run("decode", "-", stdin="01" * 3_000_000 + "\n")
    assert huge.returncode != 0 and "longer than 4096 characters" in huge.stderr
    assert len(huge.stderr.strip().splitlines()) == 1
    several = json.loads(run("decode", "-", "--json", stdin="01 03 00 00 00 01 84 0A\n" * 3).stdout)
    one = json.loads(run("decode", "-", "--json", stdin="01 03 00 00 00 01 84 0A\n").stdout)
    assert isinstance(several, list) and len(several) == 3 and one == several[0]


@pytest.mark.parametrize(("args", "expected"), [
    (("build", "--function", "22", "--address", "4", "--values", "0xF2,0x25"),
     "01 16 00 04 00 F2 00 25 67 EE"),
    (("build", "--function", "7"), "01 07 41 E2"),
    (("build", "--function", "7", "--role", "response", "--value", "0x6D"), "01 07 6D E3 DD"),
])
def test_build_knows_the_functions_beyond_the_eight(args, expected):
    assert ok(*args).splitlines()[0] == expected
    assert "Mask Write Register" in ok("decode", "01 16 00 04 00 F2 00 25 67 EE")


def test_identify_asks_device_identification_and_falls_back_to_report_server_id():
    class Old(Slave):
        def process(self, request):  # an older device: no FC 43
            if request.function_code == 0x2B:
                from modbus_edu.pdu import ExceptionResponse

                return ExceptionResponse(0x2B, 1)
            return super().process(request)

    modern = Slave(unit=1, identity={0: "ACME", 1: "PM-9", 2: "2.1"})
    with TcpServer(modern) as server:
        out = ok("identify", "--tcp", f"127.0.0.1:{server.address[1]}")
    assert "VendorName" in out and "ACME" in out and "MajorMinorRevision" in out
    with TcpServer(Old(unit=1, server_id=b"OLD-7")) as server:
        out = ok("identify", "--tcp", f"127.0.0.1:{server.address[1]}")
    assert "FC 17" in out and "OLD-7" in out and "run indicator: ON" in out


@pytest.mark.parametrize(("args", "expected"), [
    (("build", "--function", "8", "--value", "0", "--values", "0xA537"), "01 08 00 00 A5 37 DA 8D"),
    (("build", "--function", "20", "--file", "4", "--address", "1", "--count", "2"),
     "01 14 07 06 00 04 00 01 00 02 D8 E5"),
    (("build", "--function", "21", "--file", "4", "--address", "7", "--values", "0x06AF,0x04BE,0x100D"),
     "01 15 0D 06 00 04 00 07 00 03 06 AF 04 BE 10 0D D6 0B"),
    (("build", "--function", "11"), "01 0B 41 E7"),
    (("build", "--function", "12"), "01 0C 00 25"),
])
def test_build_knows_diagnostics_events_and_file_records(args, expected):
    assert ok(*args).splitlines()[0] == expected


SCAN_AND_GATEWAY_REFUSALS = register(("scan", "--serial", "loop://"), [
    (("--bauds", "12"), 2, "--bauds: 12 is not a serial speed"),
    (("--bauds", "9600,fast"), 2, "--bauds: baud rate must be a whole number"),
    (("--parities", "X"), 2, "--parities: 'X' is not a parity"),
    (("--units", "5-1"), 2, "the first unit, 5, comes after the last, 1"),
    (("--units", "0-3"), 1, "--units: the first unit must be 1..247"),
    (("--budget", "nan"), 1, "--budget must be a number of seconds"),
    (("--budget", "-5"), 1, "--budget must be a number of seconds"),
    (("--timeout", "inf"), 1, "--timeout must be a number of seconds"),
])


@pytest.mark.parametrize(("args", "code", "message"), SCAN_AND_GATEWAY_REFUSALS)
def test_scan_refuses_bad_settings_in_one_line_before_asking_anything(args, code, message):
    # one line on stderr: no progress bar was drawn before the error
    result = fails("scan", "--serial", "loop://", *args, code=code, message=message)
    assert "unexpected" not in result.stderr and "%|" not in result.stderr


GATEWAY_TIMEOUTS = register(("gateway", "--tcp", "127.0.0.1:0", "--serial", "loop://", "--timeout"),
                            [(("inf",),), (("nan",),), (("-1",),), (("0",),)])


@pytest.mark.parametrize(("args",), GATEWAY_TIMEOUTS)
def test_gateway_refuses_a_timeout_that_is_not_a_number_of_seconds(args):
    fails("gateway", "--tcp", "127.0.0.1:0", "--serial", "loop://", "--timeout", *args,
          message="--timeout must be a number of seconds from 0.001 to 3600")


def test_identify_escapes_what_a_device_says_so_it_cannot_act_on_the_terminal():
    hostile = Slave(unit=1, identity={0: "ACME\x1b[2J\x1b[H", 1: "PM-9\nfake: line", 2: "\u202e1.0\\x07\a"})
    with TcpServer(hostile) as server:
        out = ok("identify", "--tcp", f"127.0.0.1:{server.address[1]}")
    assert "\x1b" not in out and "\a" not in out and "\u202e" not in out
    assert "ACME\\x1b[2J\\x1b[H" in out and "PM-9\\nfake: line" in out and "\\u202e1.0\\\\x07\\x07" in out
    assert len(out.splitlines()) == 3

    class Old(Slave):
        def process(self, request):  # no FC 43: the command falls back to FC 17
            if request.function_code == 0x2B:
                from modbus_edu.pdu import ExceptionResponse

                return ExceptionResponse(0x2B, 1)
            return super().process(request)

    with TcpServer(Old(unit=1, server_id=b"\x1b[2J", additional_data=b"LMB\r\nv3.1.6\xff")) as server:
        out = ok("identify", "--tcp", f"127.0.0.1:{server.address[1]}")
    assert "\x1b" not in out and "\r" not in out
    assert "server ID: 1B 5B 32 4A (b'\\x1b[2J'), run indicator: ON" in out
    assert "additional data: 4C 4D 42 0D 0A 76 33 2E 31 2E 36 FF (b'LMB\\r\\nv3.1.6\\xff')" in out


# --- Modbus/TCP Security from the command line: roles apply ----------------------------------------------
@pytest.fixture(scope="module")
def pki(tmp_path_factory):
    return security.make_test_pki(tmp_path_factory.mktemp("pki"))


def _tls_args(pki) -> list[str]:
    return ["--tls-cert", str(pki.server_cert), "--tls-key", str(pki.server_key),
            "--tls-ca", str(pki.ca_cert)]


def _secure_master(pki, port: int, **context):
    link = mb.tcp_link("127.0.0.1", port, tls=security.client_context(pki, **context), timeout=5)
    return mb.Master(link, timeout=5)


def _refused(call) -> bool:
    try:
        call()
    except mb.ModbusExceptionError as exc:
        assert exc.code == 1
        return True
    return False


@contextlib.contextmanager
def _started(*args: str) -> Iterator[tuple[subprocess.Popen, int, list[str]]]:
    """A serving subcommand as a subprocess: yields it, its port and its first two lines; Ctrl-C ends it."""
    proc = subprocess.Popen([*CLI, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=ROOT, env=ENV)
    try:
        lines = [_readline(proc.stdout, 20)]
        lines.append(proc.stdout.readline())  # printed right after the first (maybe read with it already)
        port = int(lines[0].split("127.0.0.1:")[1].split(" ")[0].rstrip(";"))
        yield proc, port, lines
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=15)
        assert proc.returncode == 0 and "Traceback" not in err, err
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_serve_with_tls_applies_the_course_roles_and_says_so(pki):
    with _started("serve", "bank", "--tcp", "127.0.0.1:0", *_tls_args(pki)) as (_, port, lines):
        assert "Modbus/TCP Security" in lines[0]
        assert lines[1].startswith("roles: the course's table") and "viewer" in lines[1], lines
        viewer = _secure_master(pki, port, role="viewer")
        assert viewer.read_holding_registers(unit=1, address=1, count=1) == [1]
        assert _refused(lambda: viewer.write_single_register(unit=1, address=1, value=5))
        nobody = _secure_master(pki, port, cert=pki.no_role.cert, key=pki.no_role.key)
        assert _refused(lambda: nobody.read_holding_registers(unit=1, address=1, count=1))
        assert _refused(lambda: nobody.write_single_register(unit=1, address=1, value=5))
        engineer = _secure_master(pki, port, role="engineer")
        engineer.write_single_register(unit=1, address=1, value=5)
        assert viewer.read_holding_registers(unit=1, address=1, count=1) == [5]
        for master in (viewer, nobody, engineer):
            master.link.close()


def test_serve_and_gateway_take_a_role_file(pki, tmp_path):
    roles = tmp_path / "roles.json"
    roles.write_text(json.dumps({"roles": {"viewer": [{"functions": [3, 6], "addresses": [0, 9]}]}}))
    with _started("serve", "bank", "--tcp", "127.0.0.1:0", *_tls_args(pki), "--roles", str(roles)) \
            as (_, port, lines):
        assert lines[1].startswith(f"roles: {roles}") and "viewer" in lines[1], lines
        viewer = _secure_master(pki, port, role="viewer")
        viewer.write_single_register(unit=1, address=1, value=7)               # this table lets it write
        assert _refused(lambda: viewer.write_single_register(unit=1, address=10, value=7))
        engineer = _secure_master(pki, port, role="engineer")                  # not in this table
        assert _refused(lambda: engineer.read_holding_registers(unit=1, address=1, count=1))
        for master in (viewer, engineer):
            master.link.close()
    with _started("gateway", "--tcp", "127.0.0.1:0", "--serial", "loop://", *_tls_args(pki)) \
            as (_, port, lines):
        assert lines[1].startswith("roles: the course's table"), lines
        viewer = _secure_master(pki, port, role="viewer")
        assert _refused(lambda: viewer.write_single_register(unit=1, address=1, value=5))
        viewer.link.close()


@pytest.mark.parametrize("args, message", [
    (["serve", "bank", "--tcp", "127.0.0.1:0", "--roles", "roles.json"], "--roles needs TLS"),
    (["serve", "bank", "--tcp", "127.0.0.1:0", "--tls-cert", "c", "--tls-key", "k", "--tls-ca", "a",
      "--roles", "/no/such/roles.json"], "cannot read"),
])
def test_roles_without_tls_or_without_a_file_are_refused(args, message):
    fails(*args, message=message)
