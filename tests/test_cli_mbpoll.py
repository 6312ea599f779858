"""mbpoll (Debian's, the command-line Modbus master technicians know) as the peer of ``modbus-edu write``
and ``poll``: what one writes, the other reads back, in every value type they share, over TCP and over
RTU on a pair of ptys.

mbpoll is installed by ``.ci/run``. Without it these tests are skipped with the reason, unless the
environment variable ``CI`` is set: then a missing mbpoll FAILS them (as tshark's tests do).
"""

from __future__ import annotations

import os
import re
import select
import shutil
import subprocess
import threading
import tty

import pytest

import modbus_edu as mb
from modbus_edu.cli import main

MBPOLL = shutil.which("mbpoll")


def _in_ci() -> bool:
    return os.environ.get("CI", "").strip().lower() not in ("", "0", "false", "no")


@pytest.fixture(scope="module")
def mbpoll() -> str:
    if MBPOLL is None:
        reason = "mbpoll is not installed (apt-get install mbpoll)"
        if _in_ci():
            pytest.fail(reason + " -- and CI is set, so this is a failure, not a skip")
        pytest.skip(reason)
    return MBPOLL


@pytest.fixture()
def device():
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    with mb.TcpServer([slave]) as server:
        yield slave, server.address[1]


def run_mbpoll(port: int, *args: str) -> list[str]:
    """mbpoll once against 127.0.0.1:port; the values it prints ('[1]: 230.5' -> '230.5')."""
    result = subprocess.run(
        [MBPOLL, "-m", "tcp", "-p", str(port), "-a", "1", "-1", "-o", "2", *args, "127.0.0.1"],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    return re.findall(r"^\[\d+\]:\s+(\S+)", result.stdout, re.MULTILINE)


def ours(capsys, *argv: str) -> str:
    code = main(list(argv))
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


@pytest.mark.parametrize(
    "fmt, value, mbpoll_type",
    [
        ("unsigned", "1234", ["-t", "4"]),
        ("hex", "0xBEEF", ["-t", "4:hex"]),
        ("float32_ABCD", "230.5", ["-t", "4:float", "-B"]),
        ("float32_CDAB", "-0.125", ["-t", "4:float"]),
        ("int32_ABCD", "-123456", ["-t", "4:int", "-B"]),
        ("int32_CDAB", "2000000000", ["-t", "4:int"]),
    ],
)
def test_what_write_writes_mbpoll_reads(capsys, mbpoll, device, fmt, value, mbpoll_type):
    _, port = device
    ours(capsys, "write", "--tcp", f"127.0.0.1:{port}", "--address", "40011", "--format", fmt, "--", value)
    got = run_mbpoll(port, *mbpoll_type, "-r", "11", "-c", "1")
    assert got == [value], got


def test_what_mbpoll_writes_poll_reads(capsys, mbpoll, device):
    slave, port = device
    subprocess.run(
        [
            MBPOLL,
            "-m",
            "tcp",
            "-p",
            str(port),
            "-a",
            "1",
            "-r",
            "21",
            "-t",
            "4:int",
            "127.0.0.1",
            "--",
            "-123456",
        ],
        capture_output=True,
        timeout=30,
        check=True,
    )
    subprocess.run(
        [
            MBPOLL,
            "-m",
            "tcp",
            "-p",
            str(port),
            "-a",
            "1",
            "-r",
            "31",
            "-t",
            "4:float",
            "-B",
            "127.0.0.1",
            "230.5",
        ],
        capture_output=True,
        timeout=30,
        check=True,
    )
    subprocess.run(
        [MBPOLL, "-m", "tcp", "-p", str(port), "-a", "1", "-r", "5", "-t", "0", "127.0.0.1", "1"],
        capture_output=True,
        timeout=30,
        check=True,
    )
    where = f"127.0.0.1:{port}"
    out = ours(
        capsys,
        "poll",
        "--tcp",
        where,
        "--address",
        "40021",
        "--count",
        "2",
        "--format",
        "int32_CDAB",
        "--polls",
        "1",
    )
    assert out.startswith("#1 [20] -123456")
    out = ours(
        capsys,
        "poll",
        "--tcp",
        where,
        "--address",
        "40031",
        "--count",
        "2",
        "--format",
        "float32_ABCD",
        "--polls",
        "1",
    )
    assert out.startswith("#1 [30] 230.5")
    out = ours(capsys, "poll", "--tcp", where, "--address", "00005", "--polls", "1")
    assert out.startswith("#1 [4] 1")


def test_coils_both_ways(capsys, mbpoll, device):
    _, port = device
    ours(capsys, "write", "--tcp", f"127.0.0.1:{port}", "--address", "00001", "1", "0", "1")
    assert run_mbpoll(port, "-t", "0", "-r", "1", "-c", "3") == ["1", "0", "1"]


def test_mbpoll_reads_what_serve_serves(mbpoll):
    """``serve bank --set`` against mbpoll: the values set on the command line, read by the peer."""
    slave = mb.Slave(unit=3, bank=mb.DataBank())
    with mb.TcpServer([slave]) as server:
        slave.bank.holding_registers[0] = 42
        result = subprocess.run(
            [MBPOLL, "-m", "tcp", "-p", str(server.address[1]), "-a", "3", "-1", "-r", "1", "127.0.0.1"],
            capture_output=True,
            text=True,
            timeout=30,
        )
    assert "[1]: \t42" in result.stdout


@pytest.fixture()
def rtu_line():
    """A serial cable between two ptys: a thread copies what each end's far side writes to the other, so
    that a slave opened on one tty and mbpoll on the other talk RTU as over a real line (8N1: a Linux pty
    refuses the parity bit)."""
    ends = [os.openpty(), os.openpty()]  # (leader, follower) each
    for _, follower in ends:
        tty.setraw(follower)
    names = [os.ttyname(follower) for _, follower in ends]
    stop = threading.Event()

    def carry() -> None:
        leaders = {ends[0][0]: ends[1][0], ends[1][0]: ends[0][0]}
        while not stop.is_set():
            ready, _, _ = select.select(list(leaders), [], [], 0.05)
            for fd in ready:
                try:
                    os.write(leaders[fd], os.read(fd, 4096))
                except OSError:  # an end closed for a moment (a program opening its tty): nothing lost
                    pass

    thread = threading.Thread(target=carry, daemon=True)
    thread.start()
    yield names
    stop.set()
    thread.join(timeout=5)
    for pair in ends:
        for fd in pair:
            os.close(fd)


def run_mbpoll_rtu(tty_name: str, *args: str) -> list[str]:
    """mbpoll once as the RTU master at 19200 baud 8N1 on ``tty_name``; the values it prints."""
    result = subprocess.run([MBPOLL, "-m", "rtu", "-b", "19200", "-P", "none", "-a", "1", "-1", "-o", "2",
                             *args, tty_name], capture_output=True, text=True, timeout=30)
    assert result.returncode == 0, result.stdout + result.stderr
    return re.findall(r"^\[\d+\]:\s+(\S+)", result.stdout, re.MULTILINE)


def test_over_rtu_on_a_pair_of_ptys_each_reads_what_the_other_wrote(capsys, mbpoll, rtu_line):
    """Over RTU: mbpoll reads what ``write`` wrote, and ``poll`` reads what mbpoll wrote, through the
    library's RTU slave on the line's other end."""
    slave_end, master_end = rtu_line
    slave = mb.Slave(unit=1, bank=mb.DataBank())
    serial = ["--serial", master_end, "--baud", "19200", "--parity", "N"]
    with mb.SerialServer([slave], slave_end, baudrate=19200, parity="N"):
        ours(capsys, "write", *serial, "--address", "40011", "--format", "float32_CDAB", "--", "-0.125")
        assert run_mbpoll_rtu(master_end, "-t", "4:float", "-r", "11", "-c", "1") == ["-0.125"]
        subprocess.run([MBPOLL, "-m", "rtu", "-b", "19200", "-P", "none", "-a", "1", "-r", "21", "-t", "4",
                        master_end, "1234", "42"], capture_output=True, timeout=30, check=True)
        out = ours(capsys, "poll", *serial, "--address", "40021", "--count", "2", "--polls", "1")
    assert out.startswith("#1 [20] 1234  [21] 42"), out
    assert slave.bank.holding_registers[20] == 1234
