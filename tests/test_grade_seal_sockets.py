"""The grader never follows a link a learner's kernel made: its sockets are reached by descriptor.

A graded kernel binds its five ZeroMQ sockets in ``/tmp/run``, a folder of the grader's that the kernel
may write (it must, to bind them).  A kernel that swaps a link to a host socket in over one of them, then
stops itself for a few seconds (so that the grader's heartbeat gives up and connects again), would have
the grader (root, when grading runs as root) connect to the host socket, had the grader connected by
path.  It connects through the descriptor it opened (``O_PATH | O_NOFOLLOW``, checked to be a socket of
the kernel's user) when the kernel started: the host socket hears nothing, keeps its owner and mode,
the attacker's row says what it did, and an honest learner beside it keeps every verdict.
"""

from __future__ import annotations

import csv
import os
import shutil
import socket
import sys
import tempfile
import threading
from pathlib import Path

import pytest
from test_grade import SETUP, right, write

from modbus_edu.cli import main
from modbus_edu.course import grade as grading
from modbus_edu.course.sandbox import UID_BASE, detect, processes_marked

SANDBOX = detect()

SWAP = """import json, os, signal, time
info = json.load(open('/kernel.json'))
beat = f"{info['ip']}-{info['hb_port']}"
if os.fork() == 0:
    os.unlink(beat)
    os.symlink(%r, beat)
    os.kill(os.getppid(), signal.SIGSTOP)  # the heartbeat stops: the grader connects again
    time.sleep(4)
    os.kill(os.getppid(), signal.SIGCONT)
    os._exit(0)
time.sleep(6)"""


def _rows(out: Path) -> dict:
    with (out / "gradebook.csv").open(encoding="utf-8") as stream:
        return {row["learner"]: {k.removeprefix("'"): v for k, v in row.items()}
                for row in csv.DictReader(stream)}


@pytest.mark.skipif(SANDBOX.level != "sealed", reason=f"no sealed level here: {SANDBOX.note}")
def test_a_link_swapped_over_a_kernels_socket_is_never_followed(tmp_path):
    host = Path(tempfile.mkdtemp(prefix="modbus-edu-host-", dir="/var/tmp"))  # a host service's folder
    host.chmod(0o755)
    service = host / "service.sock"  # a socket any user may connect to (as dbus's is, under /run)
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(str(service))
    os.chmod(service, 0o666)
    listener.listen(8)
    listener.settimeout(0.2)
    heard: list[bytes] = []
    done = threading.Event()

    def serve() -> None:
        while not done.is_set():
            try:
                peer, _ = listener.accept()
            except OSError:
                continue
            with peer:
                peer.settimeout(1)
                try:
                    heard.append(peer.recv(64) or b"(connected)")
                except OSError:
                    heard.append(b"(connected)")

    before = service.lstat()
    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        write(tmp_path / "class" / "ada", "03_rtu_and_crc", [SETUP, right("03.1"), right("03.5")])
        write(tmp_path / "class" / "mallory", "03_rtu_and_crc", [SETUP, SWAP % str(service), right("03.1")])
        out = tmp_path / "grades"
        assert main(["grade", str(tmp_path / "class"), "--out", str(out), "--timeout", "60", "--jobs", "2",
                     "-q"]) == 0
    finally:
        done.set()
        thread.join(5)
        listener.close()
        after = service.lstat()
        shutil.rmtree(host, ignore_errors=True)
    assert heard == [], heard  # the grader never connected to the host's socket
    assert (after.st_uid, after.st_gid, after.st_mode) == (before.st_uid, before.st_gid, before.st_mode)
    rows = _rows(out)
    assert [rows["ada"][key] for key in ("03.1", "03.5")] == ["right", "right"], rows["ada"]
    assert rows["mallory"]["03.1"] == "right", rows["mallory"]  # its own answer, graded all the same
    assert "replaced its kernel's socket" in rows["mallory"]["flags"], rows["mallory"]["flags"]


def _uids(pid: int) -> list[int]:
    """A process's real, effective, saved and file-system user ids (empty when it is gone)."""
    try:
        lines = Path(f"/proc/{pid}/status").read_text().splitlines()
    except OSError:
        return []
    return [int(value) for line in lines if line.startswith("Uid:") for value in line.split()[1:]]


@pytest.mark.skipif(not (SANDBOX.level == "sealed" and os.geteuid() == 0), reason=(
    f"grading as root only (here: uid {os.geteuid()}, {SANDBOX.note})"))
def test_as_root_nothing_of_a_learners_runs_as_root(tmp_path):
    """Graded as root, every process of a learner's (the worker that drives its kernels, as seen from the
    host, and each process of its kernels) runs under a user id of the learner's own, never root."""
    write(tmp_path / "class" / "ada", "01_data_model", [SETUP, "import time\ntime.sleep(2)"])
    scratch = Path(tempfile.mkdtemp(prefix="modbus-edu-grade-"))
    token = f"{os.getpid()}-uid"
    seen: dict[int, tuple[str, list[int]]] = {}
    done = threading.Event()

    def watch() -> None:
        while not done.is_set():
            marked = processes_marked(f"{token}-")  # the kernels' processes, and the worker (by its line)
            for entry in Path("/proc").iterdir():
                try:
                    line = (entry / "cmdline").read_bytes() if entry.name.isdigit() else b""
                except OSError:
                    continue
                if line.startswith(f"{sys.executable}\0-m\0modbus_edu.course.runner\0{scratch}".encode()):
                    seen[int(entry.name)] = ("worker", _uids(int(entry.name)))
                elif entry.name.isdigit() and int(entry.name) in marked:
                    seen.setdefault(int(entry.name), ("kernel", _uids(int(entry.name))))
            done.wait(0.05)

    thread = threading.Thread(target=watch, daemon=True)
    thread.start()
    try:
        runs = grading._grade_learner(SANDBOX, 0, [tmp_path / "class" / "ada" / "01_data_model.ipynb"],
                                      scratch, [], 60, 1024, token)
    finally:
        done.set()
        thread.join(5)
        shutil.rmtree(scratch, ignore_errors=True)
    assert not runs[0].problems, runs[0].problems
    kinds = {kind for kind, uids in seen.values() if uids}
    assert kinds == {"kernel", "worker"}, seen
    assert all(min(uids) >= UID_BASE for _, uids in seen.values() if uids), seen
    assert "a user id of its own" in SANDBOX.note and "no capability, no_new_privs" not in SANDBOX.note
