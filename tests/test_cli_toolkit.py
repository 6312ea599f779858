"""The technician's toolkit on the command line (issue 39): reference numbers, maps, serve settable at
several units, the live table, CSV that is never overwritten unasked, decode of real logs, capture, ports,
retries, 7E1 for ASCII; and each bug of the issue, each with the test that failed before its fix."""

from __future__ import annotations

import contextlib
import os
import pty
import select
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from conftest_io import PymodbusServer, pymodbus_device

import modbus_edu as mb
from modbus_edu.cli import main
from modbus_edu.cli.live import Poller, plain_block, table_of
from modbus_edu.registermap import RegisterMapError, load_map

ROOT = Path(__file__).resolve().parents[1]
CLI = [sys.executable, "-m", "modbus_edu"]
ENV = {**os.environ, "PYTHONUNBUFFERED": "1", "PYTHONPATH": str(ROOT)}
MAPS = ROOT / "modbus_edu" / "devices" / "maps"


def cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


@pytest.fixture()
def device():
    """unit 1 on Modbus/TCP, every table holding something to tell them apart."""
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    bank = slave.bank
    bank.holding_registers[0:3] = [11, 12, 13]
    bank.input_registers[0:3] = [31, 32, 33]
    bank.coils[0:2] = [True, False]
    bank.discrete_inputs[0:2] = [False, True]
    with mb.TcpServer([slave]) as server:
        yield slave, f"127.0.0.1:{server.address[1]}"


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# --- reference numbers ---------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "address, expected",
    [
        ("40001", "#1 [0] 11  [1] 12"),
        ("4x0001", "#1 [0] 11  [1] 12"),
        ("400001", "#1 [0] 11  [1] 12"),
        ("30001", "#1 [0] 31  [1] 32"),
        ("30002", "#1 [1] 32  [2] 33"),
        ("10001", "#1 [0] 0  [1] 1"),
        ("00001", "#1 [0] 1  [1] 0"),
        ("0", "#1 [0] 11  [1] 12"),
    ],
)
def test_a_reference_number_chooses_table_and_function(capsys, device, address, expected):
    code, out, _ = cli(
        capsys, "poll", "--tcp", device[1], "--address", address, "--count", "2", "--polls", "1"
    )
    assert code == 0 and out.splitlines()[0] == expected


def test_a_reference_that_contradicts_the_function_is_an_error(capsys):
    code, _, err = cli(
        capsys, "poll", "--tcp", f"127.0.0.1:{_closed_port()}", "--function", "3", "--address", "30001"
    )
    assert code == 1
    assert (
        "30001 is a reference to the input registers, but --function 3 works on the holding registers" in err
    )


def test_a_plain_address_that_looks_like_a_reference_warns(capsys, device):
    code, out, err = cli(capsys, "poll", "--tcp", device[1], "--address", "4001", "--polls", "1")
    assert "warning: --address 4001 is read as the 0-based address 4001" in err and "40001" in err
    code, out, err = cli(capsys, "poll", "--tcp", device[1], "--address", "2", "--polls", "1")
    assert code == 0 and "warning" not in err


def test_the_help_says_which_is_which(capsys):
    with pytest.raises(SystemExit):
        main(["poll", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert (
        "0-based address (0, 100, 0x64), or a reference number" in out and "40001 = holding register 0" in out
    )


def test_one_parser_of_reference_numbers():
    from modbus_edu.datamodel import parse_address_text

    assert parse_address_text("40001").reference == mb.datamodel.parse_reference("40001")
    assert parse_address_text("0x10").address == 16 and parse_address_text("0x10").reference is None
    assert parse_address_text("99").reference is None
    with pytest.raises(mb.ModbusError, match="element numbers start at 1"):
        parse_address_text("40000")


# --- maps ----------------------------------------------------------------------------------------------
def test_the_bundled_bench_map_names_its_numbering():
    assert load_map(MAPS / "bench_meter.csv")["voltage"].address == 0  # not 30000: it says "reference"
    assert load_map(MAPS / "bench_meter.csv", numbering="reference")["current"].address == 6
    with pytest.raises(RegisterMapError, match="says '# numbering: reference'"):
        load_map(MAPS / "bench_meter.csv", numbering="0-based")


def test_a_map_that_does_not_say_is_not_guessed():
    text = "name,table,address,type\nvoltage,input,30001,uint16\n"
    with pytest.raises(RegisterMapError, match="looks like a reference number"):
        load_map(text)
    assert load_map(text, numbering="reference")["voltage"].address == 0
    assert load_map("# numbering: 0-based\n" + text)["voltage"].address == 30001
    with pytest.raises(RegisterMapError, match="numbering 'ones' must be one of"):
        load_map("# numbering: ones\n" + text)


def test_poll_a_map_by_name_scaled_with_units(capsys, tmp_path):
    register_map = load_map(MAPS / "bench_meter.csv")
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    register_map.store(slave.bank, {"voltage": 230.5, "current": 1.25})
    with mb.TcpServer([slave]) as server:
        code, out, _ = cli(
            capsys,
            "poll",
            "--tcp",
            f"127.0.0.1:{server.address[1]}",
            "--map",
            str(MAPS / "bench_meter.csv"),
            "--polls",
            "1",
            "--csv",
            str(tmp_path / "m.csv"),
        )
    assert code == 0
    assert out.splitlines()[0].startswith("#1 voltage=230.5 V  current=1.25 A  active_power=0 W")
    rows = (tmp_path / "m.csv").read_text().splitlines()
    assert rows[0].startswith("time,poll,status,voltage,current,") and ",1,ok,230.5,1.25," in rows[1]


def test_poll_several_blocks_and_a_scale(capsys, device):
    code, out, _ = cli(
        capsys,
        "poll",
        "--tcp",
        device[1],
        "--address",
        "40001",
        "--count",
        "2",
        "--scale",
        "0.1",
        "--block",
        "30003",
        "--block",
        "00001:2",
        "--polls",
        "1",
    )
    assert code == 0
    assert out.splitlines()[0] == "#1 [40001] 1.1  [40002] 1.2  [30003] 33  [00001] 1  [00002] 0"


# --- serve: settable, several units, a map --------------------------------------------------------------
@contextlib.contextmanager
def serving(*args: str):
    proc = subprocess.Popen(
        [*CLI, *args, "--tcp", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
        env=ENV,
    )
    try:
        ready, _, _ = select.select([proc.stdout], [], [], 60)
        assert ready, "serve printed nothing"
        line = proc.stdout.readline()
        assert "serving" in line, line + proc.stderr.read()
        yield proc, int(line.split("127.0.0.1:")[1].split(";")[0])
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_serve_a_map_with_values_at_several_units(capsys, tmp_path):
    values = tmp_path / "values.txt"
    values.write_text("# set at start\ncurrent=2.5\n00003=on\n")
    with serving(
        "-v",
        "serve",
        "bank",
        "--unit",
        "1",
        "--unit",
        "2",
        "--map",
        str(MAPS / "bench_meter.csv"),
        "--set",
        "voltage=231.25",
        "--set",
        "40001=1234",
        "--set",
        "40011:float32_CDAB=1.5",
        "--values",
        str(values),
    ) as (proc, port):
        where = f"127.0.0.1:{port}"
        for unit in ("1", "2"):
            code, out, _ = cli(
                capsys,
                "poll",
                "--tcp",
                where,
                "--unit",
                unit,
                "--map",
                str(MAPS / "bench_meter.csv"),
                "--polls",
                "1",
            )
            assert out.splitlines()[0].startswith("#1 voltage=231.25 V  current=2.5 A")
        code, out, _ = cli(
            capsys,
            "poll",
            "--tcp",
            where,
            "--address",
            "40011",
            "--count",
            "2",
            "--format",
            "float32_CDAB",
            "--polls",
            "1",
        )
        assert out.startswith("#1 [10] 1.5")
        code, out, _ = cli(capsys, "poll", "--tcp", where, "--address", "00003", "--polls", "1")
        assert out.startswith("#1 [2] 1")
        # a unit nobody serves: answered 0x0B, and counted and shown (-v) by serve
        code, out, _ = cli(capsys, "poll", "--tcp", where, "--unit", "9", "--polls", "1")
        assert "exception 0B" in out
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0
    assert "other units (0x0B): 1" in out
    assert "no slave at unit 9" in err and "answered 0x0B" in err


def test_serve_bank_set_errors_are_one_line(capsys):
    for args, message in (
        (["--set", "voltage=1"], "neither a point name nor a reference number"),
        (["--set", "5=1"], "is a plain address"),
        (["--set", "40001"], "is not NAME=VALUE"),
        (["--unit", "1", "--unit", "1"], "each --unit once"),
    ):
        code, _, err = cli(capsys, "serve", "bank", "--tcp", "127.0.0.1:0", *args)
        assert code == 1 and len(err.strip().splitlines()) == 1 and message in err, err
    code, _, err = cli(capsys, "serve", "meter", "--set", "40001=1")
    assert code == 1 and "use 'serve bank'" in err


def test_serve_stops_promptly_on_sigint_with_a_client_connected():
    with serving("serve", "bank") as (proc, port):
        client = socket.create_connection(("127.0.0.1", port))
        client.sendall(bytes.fromhex("000100000006010300000001"))
        assert client.recv(64)
        started = time.monotonic()
        proc.send_signal(signal.SIGINT)
        ready, _, _ = select.select([proc.stdout], [], [], 5)
        line = proc.stdout.readline()
        stopped = time.monotonic() - started
        client.close()
        proc.communicate(timeout=20)
    assert line.startswith("stopped:") and stopped < 0.5, (line, stopped)
    assert proc.returncode == 0


# --- the live table, lines, CSV -------------------------------------------------------------------------
def test_the_live_table_shows_names_values_status_times_and_rates(device):
    from rich.console import Console

    with mb.tcp_link("127.0.0.1", int(device[1].split(":")[1])) as link:
        master = mb.Master(link, timeout=2)
        poller = Poller(master, 1, [plain_block(3, 0, 2, "unsigned", 0.5), plain_block(4, 5, 1, "hex")])
        poller.cycle()
        poller.cycle()
        console = Console(record=True, width=160, color_system=None)
        console.print(table_of(poller, 1, device[1]))
    text = console.export_text()
    assert "poll 2" in text and "polls/s" in text
    assert "00 0B" in text and "5.5" in text and "6" in text  # raw 11, scaled by 0.5
    assert "exception 02" not in text and "ok" in text and "2/0/0/0" in text
    assert "FC 3 0..1 (4x0001)" in text and "FC 4 5..5 (3x0006)" in text


def test_poll_on_a_terminal_redraws_a_table_in_place(device):
    leader, follower = pty.openpty()
    proc = subprocess.Popen(
        [
            *CLI,
            "poll",
            "--tcp",
            device[1],
            "--address",
            "40001",
            "--count",
            "2",
            "--polls",
            "3",
            "--interval",
            "0.05",
        ],
        stdout=follower,
        stderr=follower,
        stdin=subprocess.DEVNULL,
        cwd=ROOT,
        env={**ENV, "COLUMNS": "150", "TERM": "xterm"},
    )
    os.close(follower)
    chunks = []
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        ready, _, _ = select.select([leader], [], [], 1)
        if ready:
            try:
                data = os.read(leader, 65536)
            except OSError:
                break
            if not data:
                break
            chunks.append(data)
        elif proc.poll() is not None:
            break
    proc.wait(timeout=30)
    os.close(leader)
    screen = b"".join(chunks).decode("utf-8", "replace")
    assert proc.returncode == 0, screen
    assert "\x1b[" in screen and "poll 3" in screen  # redrawn (cursor moves), up to the third poll
    assert "┃" in screen or "│" in screen  # a table, not lines
    assert "#1 [0]" not in screen


def test_csv_is_never_overwritten_unasked(capsys, device, tmp_path):
    log = tmp_path / "log.csv"
    base = ["poll", "--tcp", device[1], "--address", "40001", "--polls", "1", "--csv", str(log)]
    assert cli(capsys, *base)[0] == 0
    code, _, err = cli(capsys, *base)
    assert code == 1 and "already exists: add --append" in err
    assert cli(capsys, *base, "--append")[0] == 0
    rows = log.read_text().splitlines()
    assert len(rows) == 3 and rows[0] == "time,poll,status,0" and rows.count(rows[0]) == 1
    assert cli(capsys, *base, "--overwrite")[0] == 0
    assert len(log.read_text().splitlines()) == 2
    code, _, err = cli(
        capsys,
        "poll",
        "--tcp",
        device[1],
        "--address",
        "30001",
        "--polls",
        "1",
        "--csv",
        str(log),
        "--append",
    )
    assert code == 0, err  # the same columns (address 0, here of the input registers): appended
    code, _, err = cli(
        capsys, "poll", "--tcp", device[1], "--count", "2", "--polls", "1", "--csv", str(log), "--append"
    )
    assert code == 1 and "has other columns" in err


def test_a_format_wider_than_the_count_fails_clearly(capsys, device, tmp_path):
    log = tmp_path / "wide.csv"
    code, out, err = cli(
        capsys,
        "poll",
        "--tcp",
        device[1],
        "--count",
        "2",
        "--format",
        "float64_ABCD",
        "--polls",
        "1",
        "--csv",
        str(log),
    )
    assert code == 1 and "float64_ABCD needs 4 registers per value, but --count 2 reads 2" in err
    assert not log.exists() and "—" not in out
    code, _, err = cli(capsys, "poll", "--tcp", device[1], "--count", "3", "--format", "float32_ABCD")
    assert code == 1 and "leaves 1 over" in err


def test_retries_ask_again(capsys):
    with socket.socket() as mute:
        mute.bind(("127.0.0.1", 0))
        mute.listen(1)
        code, out, _ = cli(
            capsys,
            "poll",
            "--tcp",
            f"127.0.0.1:{mute.getsockname()[1]}",
            "--polls",
            "1",
            "--timeout",
            "0.05",
            "--retries",
            "2",
        )
    assert code == 1 and "stats: requests 3, valid 0, timeouts 3" in out


def test_ascii_is_7e1_by_default(monkeypatch, capsys):
    seen = {}

    def fake_serial_link(url, **kwargs):
        seen.update(kwargs)
        raise mb.ModbusError("no port here")

    monkeypatch.setattr("modbus_edu.cli.common.serial_link", fake_serial_link)
    cli(capsys, "poll", "--serial", "loop://", "--mode", "ascii")
    assert seen["parity"] == "E"
    cli(capsys, "poll", "--serial", "loop://")
    assert seen["parity"] == "N"
    cli(capsys, "poll", "--serial", "loop://", "--mode", "ascii", "--parity", "n")
    assert seen["parity"] == "N"


# --- decode: real logs ----------------------------------------------------------------------------------
LOG = """\
000001-Tx:01 03 00 00 00 02 C4 0B
000002-Rx:01 03 04 42 F6 E9 79 80 0B
this line is not a frame
2024-01-02 12:00:01.250 Tx: 01:03:00:00:00:01:84:0A Rx: 01,03,02,00,01,79,84
[12:00:01.300] 01 03 00 00 00 01 84 0A 01 03 02 00 01 79 84
12:00:02.000 00 05 00 00 00 06 01 03 00 00 00 01 00 05 00 00 00 05 01 03 02 00 07
"""


def _decode_stdin(monkeypatch, capsys, text: str, *argv: str) -> tuple[int, str, str]:
    import io

    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text.encode())))
    return cli(capsys, "decode", *argv, "-")


def test_decode_reads_a_log_as_tools_write_it(monkeypatch, capsys):
    code, out, err = _decode_stdin(monkeypatch, capsys, LOG, "--as", "float32_ABCD")
    assert code == 1  # a line held no frame: said, and the exit status says so at the end
    assert "line 3: skipped, no frame in it" in err
    assert (
        err.strip().splitlines()[-1]
        == "modbus-edu: error: 1 line held no frame (see above); 8 frames decoded"
    )
    assert out.count("line 4:") == 2 and out.count("line 5:") == 2 and out.count("line 6:") == 2
    assert "as float32_ABCD: 123.456" in out
    assert "Modbus/TCP" in out or "transaction" in out.lower()


def test_decode_as_needs_enough_registers(monkeypatch, capsys):
    code, out, _ = cli(capsys, "decode", "--as", "float32_ABCD", "01 03 02 00 01 79 84")
    assert code == 0 and "as float32_ABCD: 1 register(s), too few for one value" in out


def test_decode_auto_says_a_bad_mbap_length_is_a_tcp_frame(capsys):
    code, out, err = cli(capsys, "decode", "00 01 00 00 00 09 01 03 00 00 00 01")
    assert code == 1
    assert "MBAP length at bytes 4-5 is 9" in err and "CRC" not in err


# --- capture, ports --------------------------------------------------------------------------------------
def test_capture_pairs_requests_and_responses_with_times(capsys, tmp_path):
    bank = mb.DataBank(sparse=True)
    bank.holding_registers.declare(0, 10)
    bus = mb.loopback_serial(mb.Slave(unit=1, bank=bank), baudrate=9600)
    master = mb.Master(bus)
    master.read_holding_registers(1, 0, 2)
    master.write_single_register(1, 3, 7)
    with pytest.raises(mb.ModbusExceptionError):
        master.read_holding_registers(1, 100, 1)  # not declared: exception 02
    path = tmp_path / "rtu.pcap"
    mb.write_pcap(master.log, path)
    code, out, _ = cli(capsys, "capture", str(path))
    lines = out.splitlines()
    assert code == 0
    assert "request   Read Holding Registers request: address 0, count 2" in lines[0]
    assert "(answers #1 after " in lines[1] and " ms)" in lines[1]
    assert "exception" in lines[5].lower() and "(answers #5 after" in lines[5]
    assert (
        lines[-1] == "6 frames: 3 exchanges, 0 requests without a response, 0 responses without a "
        "request, 0 not decodable"
    )


def test_capture_of_tcp_and_bad_files(capsys, tmp_path):
    link = mb.loopback_tcp(mb.Slave(unit=1, bank=mb.DataBank()))
    master = mb.Master(link)
    master.read_input_registers(1, 0, 1)
    path = tmp_path / "tcp.pcapng"
    mb.write_pcap(master.log, path)
    code, out, _ = cli(capsys, "capture", "--full", str(path))
    assert code == 0 and "(answers #1 after" in out and "transaction identifier" in out
    bad = tmp_path / "bad.pcap"
    bad.write_bytes(b"not a capture")
    code, _, err = cli(capsys, "capture", str(bad))
    assert code == 1 and len(err.strip().splitlines()) == 1


def test_ports_lists_what_pyserial_finds(monkeypatch, capsys):
    from serial.tools import list_ports_common

    port = list_ports_common.ListPortInfo("/dev/ttyUSB0")
    port.description, port.hwid = "USB-RS485 adapter", "USB VID:PID=0403:6001"
    monkeypatch.setattr("serial.tools.list_ports.comports", lambda include_links=False: [port])
    assert cli(capsys, "ports")[1] == "/dev/ttyUSB0  USB-RS485 adapter  USB VID:PID=0403:6001\n"
    monkeypatch.setattr("serial.tools.list_ports.comports", lambda include_links=False: [])
    assert cli(capsys, "ports")[1].startswith("no serial ports found")


# --- bugs from the issue ---------------------------------------------------------------------------------
class SlowGateway:
    """A Modbus/TCP gateway whose only slave is unit 5, slower than the scan's timeout: every answer (the
    slave's, or 0x0B for the other units) comes ``delay`` s after its request, with its own transaction id."""

    def __init__(self, delay: float) -> None:
        self.delay = delay
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.port = self.listener.getsockname()[1]
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.stop = threading.Event()

    def _serve(self) -> None:
        self.listener.settimeout(10)
        with contextlib.suppress(OSError):
            conn, _ = self.listener.accept()
            conn.settimeout(0.05)
            pending: list[tuple[float, bytes]] = []
            while not self.stop.is_set():
                with contextlib.suppress(socket.timeout):
                    data = conn.recv(12)
                    if not data:
                        return
                    tid, unit = data[0:2], data[6]
                    if unit == 5:
                        answer = tid + bytes.fromhex("0000 0005 05 03 02 002A")
                    else:
                        answer = tid + bytes([0, 0, 0, 3, unit, 0x83, 0x0B])
                    pending.append((time.monotonic() + self.delay, answer))
                while pending and pending[0][0] <= time.monotonic():
                    conn.sendall(pending.pop(0)[1])

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.stop.set()
        self.listener.close()
        self.thread.join(10)


def test_scan_through_a_slow_gateway_invents_no_units(capsys):
    with SlowGateway(delay=0.15) as gateway:
        code, out, _ = cli(
            capsys, "scan", "--tcp", f"127.0.0.1:{gateway.port}", "--units", "1-10", "--timeout", "0.1"
        )
    assert code == 0
    assert "unit   6" not in out and out.splitlines()[-2] == "0 found, 10 asked"  # no unit invented
    assert out.splitlines()[-1].startswith("note: ") and "longer --timeout" in out
    with SlowGateway(delay=0.05) as gateway:
        code, out, _ = cli(
            capsys, "scan", "--tcp", f"127.0.0.1:{gateway.port}", "--units", "1-10", "--timeout", "0.5"
        )
    assert out.splitlines() == ["unit   5: register 0 = 42", "1 found, 10 asked"]


def test_identify_with_no_objects_says_so_and_asks_fc17(capsys):
    with PymodbusServer(pymodbus_device(1)) as server:  # pymodbus answers FC 43/14 with zero objects
        code, out, err = cli(capsys, "-v", "identify", "--tcp", f"127.0.0.1:{server.port}", "--timeout", "2")
    assert code == 0
    assert "with no objects at all" in out and "asking Report Server ID (FC 17)" in out
    assert "server ID: 50 79 6D 6F 64 62 75 73 (b'Pymodbus')" in out
    assert err.count("tx -> ") == 2 and err.count("rx <- ") == 2  # -v shows identify's traffic


def test_scan_verbose_shows_the_traffic(capsys, device):
    code, out, err = cli(capsys, "-v", "scan", "--tcp", device[1], "--units", "1-2", "--timeout", "0.5")
    assert code == 0 and err.count("tx -> ") == 2 and "rx <- " in err


def test_build_lists_every_buildable_function(capsys):
    code, _, err = cli(capsys, "build", "--function", "99", "--address", "0")
    assert code == 1
    for fc in ("17", "22", "43", "23", "8", "24"):
        assert f" {fc}," in err or f" {fc}" in err.rstrip().split(":")[-1]
    assert (
        "the 19 this library builds: 1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 15, 16, 17, 20, 21, 22, 23, 24, 43"
        in err
    )


def _scan_process(port: int, ignore_sigint: bool) -> subprocess.Popen:
    def background_job():  # as a shell starts a job with &: SIGINT ignored
        signal.signal(signal.SIGINT, signal.SIG_IGN)

    return subprocess.Popen(
        [*CLI, "scan", "--tcp", f"127.0.0.1:{port}", "--units", "1-247", "--timeout", "0.2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
        env=ENV,
        preexec_fn=background_job if ignore_sigint else None,
    )


@pytest.mark.parametrize("ignore_sigint", [False, True])
def test_scan_stops_at_sigint_and_says_so(ignore_sigint):
    """Ctrl-C, or SIGINT to a background job (started with SIGINT ignored), stops the scan at once."""
    with SlowGateway(delay=10) as gateway:  # answers nothing in time: every unit takes the full 0.2 s
        proc = _scan_process(gateway.port, ignore_sigint)
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:  # wait until the progress bar shows a unit or two asked
            ready, _, _ = select.select([proc.stderr], [], [], 1)
            if ready and "unit" in os.read(proc.stderr.fileno(), 4096).decode(errors="replace"):
                break
        time.sleep(0.5)
        started = time.monotonic()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
        took = time.monotonic() - started
    assert proc.returncode == 130, err
    assert out.splitlines()[-1].endswith("(interrupted)") and "Traceback" not in err
    assert took < 3


def test_scan_report_keeps_hits_when_interrupted(monkeypatch):
    """The library's scan: a KeyboardInterrupt keeps the hits found so far."""
    scan_module = sys.modules["modbus_edu.scan"]  # (mb.scan is the function of the same name)

    class Bar:  # a progress bar whose third update is where Ctrl-C lands
        updates = 0

        def __init__(self, **kwargs):
            pass

        def update(self, n):
            Bar.updates += 1
            if Bar.updates == 3:
                raise KeyboardInterrupt

        def set_postfix(self, **kwargs):
            pass

        def close(self):
            pass

    monkeypatch.setattr(scan_module, "load_tqdm", lambda: Bar)
    bus = mb.loopback_serial([mb.Slave(unit=1, bank=mb.DataBank())], baudrate=9600)
    report = scan_module.scan(bus, range(1, 20), timeout=0.05)
    assert report.interrupted and not report.complete
    assert [h.unit for h in report] == [1] and report.asked == 3


def test_a_command_run_in_process_gives_the_signals_back(capsys):
    """poll, scan, serve and gateway make Ctrl-C and SIGTERM stop them; run inside another program (a
    test, a notebook's kernel), the command gives that program its own handlers back when it returns."""
    before = [signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)]
    with socket.socket() as probe:  # a port nobody listens on: the scan stops at once, refused
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    status = main(["scan", "--tcp", f"127.0.0.1:{port}", "--units", "1", "--timeout", "0.05"])
    capsys.readouterr()
    assert status != 0
    assert [signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)] == before
